//! Linear-elasticity mesh deformation (the kernel's `elasticity` module, SU2_DEF's method):
//! `dk_elasticity_graph_len` / `dk_elasticity_graph` (the cell-pair graph the stiffness lives
//! on), `dk_elasticity_scratch_len` and `dk_elasticity_deform` (load increments with
//! re-assembly, block-Jacobi CG), with `dk_elasticity_options_default`.
//!
//! Cells are read in `index_base` 0 or 1; with 1 the 0-based copies go to the caller's
//! `uint32_t` `index_scratch` (`cells->offsets_len + cells->nodes_len` entries).

use deform_kernel::elasticity::{
    deform_incremental, elasticity_graph, elasticity_graph_len, Block, IncrementBuffers,
    IncrementReport, Increments, Modulus,
};
use deform_kernel::spring::SolveOptions;
use deform_kernel::{Graph, Real};
use deform_kernel_ffi_export::export;

use crate::args::{assert_layout, mul_len, optional, read_one, write_len, write_one, Dim};
use crate::graph::{dk_cells, dk_graph, read_graph, CellsIn};
use crate::slice::{chunks, chunks_mut, input, out_one, output, In, Out};
use crate::status::dk_status;

/// [`dk_elasticity_options::modulus`]: `E = 1` in every cell (SU2 `CONSTANT_STIFFNESS`).
pub const DK_MODULUS_CONSTANT: u32 = 0;
/// [`dk_elasticity_options::modulus`]: `E = 1/V` (SU2 `INVERSE_VOLUME`, the default).
pub const DK_MODULUS_INVERSE_VOLUME: u32 = 1;
/// [`dk_elasticity_options::modulus`]: `E = 1/d`, `d` the cell's mean wall distance (SU2
/// `WALL_DISTANCE`; needs `wall_distance`).
pub const DK_MODULUS_WALL_DISTANCE: u32 = 2;

/// Material, increments and stopping rules of `dk_elasticity_deform`. Fill with
/// `dk_elasticity_options_default` (or `_f32`) and change fields as needed.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_elasticity_options {
    /// CG iteration cap of each increment. Default 10 000.
    pub max_iterations: usize,
    /// Relative residual tolerance of each increment's solve (finite, ≥ 0). Default
    /// `max(1e-10, 100 ε)`.
    pub residual_tol: f64,
    /// Poisson ratio: in (−1, ½), or above ½ for SU2's `DEFORM_COEFF` convention (λ ≈ −μ;
    /// `DK_ERR_SINGULAR_SYSTEM` if the operator is then not positive definite). Default 0.3.
    pub poisson: f64,
    /// Load increments, at least 1. Default 1.
    pub steps: u32,
    /// `DK_MODULUS_CONSTANT`, `DK_MODULUS_INVERSE_VOLUME` (default) or
    /// `DK_MODULUS_WALL_DISTANCE`.
    pub modulus: u32,
}
assert_layout!(
    dk_elasticity_options, 32;
    max_iterations = 0, residual_tol = 8, poisson = 16, steps = 24, modulus = 28,
);

/// What `dk_elasticity_deform` did. A step that did not converge is reported here
/// (`converged` false, status `DK_OK`), never hidden.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_elasticity_report {
    /// Increments taken.
    pub steps: usize,
    /// CG iterations of all increments.
    pub iterations: usize,
    /// The most iterations one increment needed.
    pub max_step_iterations: usize,
    /// The largest final relative residual of an increment.
    pub residual: f64,
    /// Whether every increment's solve converged.
    pub converged: bool,
}
assert_layout!(
    dk_elasticity_report, 40;
    steps = 0, iterations = 8, max_step_iterations = 16, residual = 24, converged = 32,
);

impl dk_elasticity_report {
    /// The C report of the kernel's.
    pub(crate) fn of<T: Real>(r: IncrementReport<T>) -> Self {
        dk_elasticity_report {
            steps: r.steps,
            iterations: r.iterations,
            max_step_iterations: r.max_step_iterations,
            residual: r.residual.to_f64(),
            converged: r.converged,
        }
    }
}

impl dk_elasticity_options {
    /// The kernel's increments (modulus and Poisson ratio checked by the kernel).
    pub(crate) fn increments<'w, T: Real>(
        &self,
        wall_distance: Option<&'w [T]>,
    ) -> Result<Increments<'w, T>, dk_status> {
        Ok(Increments {
            modulus: self.modulus()?,
            wall_distance,
            poisson: T::from_f64(self.poisson),
            steps: self.steps as usize,
        })
    }

    /// The stopping rules of each increment's solve.
    pub(crate) fn solve_options<T: Real>(&self) -> SolveOptions<T> {
        SolveOptions {
            max_iterations: self.max_iterations,
            residual_tol: T::from_f64(self.residual_tol),
            update_tol: T::ZERO,
        }
    }

    fn modulus(&self) -> Result<Modulus, dk_status> {
        Ok(match self.modulus {
            DK_MODULUS_CONSTANT => Modulus::Constant,
            DK_MODULUS_INVERSE_VOLUME => Modulus::InverseVolume,
            DK_MODULUS_WALL_DISTANCE => Modulus::WallDistance,
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        })
    }
}

/// Scalars of `scratch` [`dk_elasticity_deform`] needs: `cell_count + dim²·(node_count +
/// edge_count) + 6·dim·node_count` (the increments' buffers, then the four CG vectors);
/// `edge_count` is the graph's `targets_len`.
fn scratch_scalars(
    cells: usize,
    nodes: usize,
    edges: usize,
    dim: usize,
) -> Result<usize, dk_status> {
    increment_scalars(cells, nodes, edges, dim)?
        .checked_add(mul_len(mul_len(4, dim)?, nodes)?)
        .ok_or(dk_status::DK_ERR_TOO_LARGE)
}

/// Scalars of the increments' own buffers: `cell_count + dim²·(node_count + edge_count) +
/// 2·dim·node_count` (moduli, node and edge blocks, the current mesh, the increment).
pub(crate) fn increment_scalars(
    cells: usize,
    nodes: usize,
    edges: usize,
    dim: usize,
) -> Result<usize, dk_status> {
    let blocks = mul_len(
        mul_len(dim, dim)?,
        nodes
            .checked_add(edges)
            .ok_or(dk_status::DK_ERR_TOO_LARGE)?,
    )?;
    let vectors = mul_len(mul_len(2, dim)?, nodes)?;
    cells
        .checked_add(blocks)
        .and_then(|s| s.checked_add(vectors))
        .ok_or(dk_status::DK_ERR_TOO_LARGE)
}

/// The increments' buffers carved from the front of `scratch` (in the order of
/// [`increment_scalars`]) and the rest of it.
pub(crate) fn increment_buffers<T, const D: usize>(
    scratch: &mut [T],
    cells: usize,
    n: usize,
    e: usize,
) -> Result<(IncrementBuffers<'_, T, D>, &mut [T]), dk_status> {
    let short = dk_status::DK_ERR_BUFFER_TOO_SMALL;
    let (moduli, rest) = scratch.split_at_mut_checked(cells).ok_or(short)?;
    let (diag, rest) = rest.split_at_mut_checked(mul_len(D * D, n)?).ok_or(short)?;
    let (off, rest) = rest.split_at_mut_checked(mul_len(D * D, e)?).ok_or(short)?;
    let (current, rest) = rest.split_at_mut_checked(mul_len(D, n)?).ok_or(short)?;
    let (step, rest) = rest.split_at_mut_checked(mul_len(D, n)?).ok_or(short)?;
    let buffers = IncrementBuffers {
        moduli,
        diag: blocks::<T, D>(diag),
        off: blocks::<T, D>(off),
        current: current.as_chunks_mut::<D>().0,
        step: step.as_chunks_mut::<D>().0,
    };
    Ok((buffers, rest))
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Length `targets` needs for [`dk_elasticity_graph`]: `Σ n_c (n_c − 1)` over the cells
/// (validates the cells first; `index_scratch` as in `dk_cells_check`).
#[export(cells[1], len_out[1])]
pub(crate) fn dk_elasticity_graph_len(
    node_count: usize,
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let scratch = output(index_scratch)?;
    let (cells, _) = CellsIn::read(cells)?.cells(node_count, index_base, scratch)?;
    write_len(len_out, elasticity_graph_len(&cells))
}

/// Builds the graph of every pair of nodes that share a cell (the sparsity of the
/// elasticity stiffness: a hexahedron couples all its nodes) as a symmetric, sorted,
/// deduplicated 0-based CSR graph. `offsets` must have `node_count + 1` entries, `targets` at
/// least [`dk_elasticity_graph_len`]; `*used_out` receives the entries used.
#[export(cells[1], used_out[1])]
pub(crate) fn dk_elasticity_graph(
    node_count: usize,
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    offsets: Out<'_, u32>,
    targets: Out<'_, u32>,
    used_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let scratch = output(index_scratch)?;
    let (cells, _) = CellsIn::read(cells)?.cells(node_count, index_base, scratch)?;
    let (o, t, used) = (output(offsets)?, output(targets)?, out_one(used_out)?);
    *used = elasticity_graph(&cells, o, t)?;
    Ok(())
}

/// Scalars of `scratch` [`dk_elasticity_deform`] needs: `cell_count + dim²·(node_count +
/// edge_count) + 6·dim·node_count`, `edge_count` the graph's `targets_len` (the same count
/// for both precisions).
#[export(len_out[1])]
pub(crate) fn dk_elasticity_scratch_len(
    node_count: usize,
    cell_count: usize,
    edge_count: usize,
    dim: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    if !(2..=3).contains(&dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let n = scratch_scalars(cell_count, node_count, edge_count, dim as usize)?;
    write_len(len_out, n)
}

/// Fills `*out` with the default elasticity settings for f64: inverse-volume modulus,
/// Poisson ratio 0.3, one increment, 10 000 iterations, residual tolerance 1e-10.
///
/// # f32 twin
/// As [`dk_elasticity_options_default`] with the f32 default residual tolerance
/// (`100 ε_f32` ≈ 1.19e-5).
#[export(twin, out[1])]
pub(crate) fn dk_elasticity_options_default<T: Real>(
    out: Out<'_, dk_elasticity_options>,
) -> Result<(), dk_status> {
    let s = SolveOptions::<T>::default();
    let v = dk_elasticity_options {
        max_iterations: s.max_iterations,
        residual_tol: s.residual_tol.to_f64(),
        poisson: 0.3,
        steps: 1,
        modulus: DK_MODULUS_INVERSE_VOLUME,
    };
    write_one(out, v)
}

/// `D×D` blocks carved from a flat scalar slice.
pub(crate) fn blocks<T, const D: usize>(flat: &mut [T]) -> &mut [Block<T, D>] {
    flat.as_chunks_mut::<D>().0.as_chunks_mut::<D>().0
}

/// Moves a mesh by linear elasticity (SU2_DEF's method) in `options->steps` load increments:
/// the nodes with a nonzero `fixed` byte move by `displacement` (`node_count * dim` scalars,
/// read at fixed nodes only), `1/steps` of it per increment; before each, the moduli
/// (`options->modulus`; `wall_distance`, one per node, for `DK_MODULUS_WALL_DISTANCE`, else
/// NULL with length 0) and the stiffness are recomputed on the current mesh and the free
/// nodes follow by block-Jacobi CG. `points` (`node_count * dim` scalars) holds the mesh and
/// receives the moved one; the fixed nodes end at `points + displacement` exactly. `graph`
/// comes from [`dk_elasticity_graph`]; `scratch` needs [`dk_elasticity_scratch_len`]
/// scalars. On any error `points` is unchanged.
#[export(twin, cells[1], graph[1], options[1], report[1])]
pub(crate) fn dk_elasticity_deform<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    options: In<'_, dk_elasticity_options>,
    wall_distance: In<'_, T>,
    displacement: In<'_, T>,
    points: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_elasticity_report>,
) -> Result<(), dk_status> {
    let out = out_one(report)?;
    let options = read_one(options)?;
    let n = points.len() / D;
    let (cells, _) = CellsIn::read(cells)?.cells(n, index_base, output(index_scratch)?)?;
    let graph: Graph<'_> = read_graph(graph)?;
    let e = graph.edge_count();
    let need = scratch_scalars(cells.len(), n, e, D)?;
    let scratch = output(scratch)?;
    if scratch.len() < need {
        return Err(dk_status::DK_ERR_BUFFER_TOO_SMALL);
    }
    if displacement.len() != points.len() {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let (buffers, cg) = increment_buffers::<T, D>(scratch, cells.len(), n, e)?;
    let cg = cg.as_chunks_mut::<D>().0;
    let params = options.increments(optional(wall_distance)?)?;
    let solve_options = options.solve_options();
    let r = deform_incremental(
        &cells,
        &graph,
        input(fixed)?,
        &params,
        chunks_mut::<T, D>(points)?,
        chunks::<T, D>(displacement)?,
        buffers,
        |sys, u| sys.solve(u, &solve_options, cg),
    )?;
    *out = dk_elasticity_report::of(r);
    Ok(())
}
