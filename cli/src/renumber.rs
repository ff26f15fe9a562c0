//! `deform move --renumber`: the solve runs on the mesh renumbered for memory locality
//! (reverse Cuthill–McKee on the edge graph, or a Hilbert curve through the points), and the
//! result comes back in the input's numbering.
//!
//! The run is exactly "renumber the mesh, run the same method, put the nodes back": the
//! points, cells, marker elements, sliding markers and prescribed displacements are all
//! renumbered, `run_move_in_steps` runs on them unchanged, and the deformed points and
//! displacements are permuted back, so the output is bit-identical to the same method run on
//! the renumbered mesh file and un-permuted (tests/move_renumber.rs checks it).
//!
//! `auto` renumbers by RCM when the mesh is large enough for cache misses to matter
//! ([`AUTO_MIN_NODES`]) and its numbering is far from local: the mean index distance across
//! cell edges is above [`AUTO_SPREAD`] times `n^((d−1)/d)`, the distance a numbering along
//! grid lines or fronts has. A mesh numbered that way (every generated or structured mesh,
//! every mesh a solver already ordered) is left alone, bits included.

use std::time::Instant;

use clap::ValueEnum;
use deform_kernel::order::{
    hilbert_order, permute, permute_graph, rcm_order, IndexDistance, Permutation,
};
use deform_kernel::{CellKind, Graph};
use serde::Serialize;

use crate::engine::SlideMarker;
use crate::engine::{
    cells_view, edge_graph, points_d, run_move_in_steps, MoveInput, MoveResult, OwnedGraph,
};
use crate::error::CliError;
use crate::formats::CellList;
use crate::motion::Motion;

/// How `deform move` numbers the nodes for the solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Renumber {
    /// RCM when the mesh has at least 20 000 nodes and its numbering scatters neighbours
    /// (mean index distance across edges above 8 n^((d-1)/d)); otherwise as given.
    #[default]
    Auto,
    /// The input's numbering.
    Off,
    /// Reverse Cuthill–McKee on the edge graph.
    Rcm,
    /// A Hilbert curve through the points.
    Hilbert,
}

/// Smallest mesh `auto` renumbers: below it the solve's arrays fit the caches.
pub const AUTO_MIN_NODES: usize = 20_000;
/// `auto` renumbers when the mean index distance exceeds this many `n^((d−1)/d)`.
pub const AUTO_SPREAD: f64 = 8.0;

/// What the renumbering did, for the report.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RenumberReport {
    /// `off`, `rcm` or `hilbert`: what ran.
    pub method: &'static str,
    /// Mean index distance across the cells' edges before (each cell's edges; `None`:
    /// `--renumber off`, not measured).
    pub mean_distance_before: Option<f64>,
    /// After (equal to before when nothing was renumbered).
    pub mean_distance_after: Option<f64>,
    /// Largest index distance before.
    pub bandwidth_before: Option<u32>,
    /// Largest index distance after.
    pub bandwidth_after: Option<u32>,
    /// Seconds spent choosing, ordering and permuting (in and out).
    pub seconds: f64,
}

/// A permutation with its two arrays owned, and the edge graph RCM ordered (in the input's
/// numbering), kept so that the solve does not build it again.
struct Order {
    order: Vec<u32>,
    inverse: Vec<u32>,
    graph: Option<OwnedGraph>,
}

impl Order {
    fn view(&self) -> Result<Permutation<'_>, CliError> {
        Permutation::new(&self.order, &self.inverse).map_err(kernel)
    }
}

fn kernel(source: deform_kernel::Error) -> CliError {
    CliError::Kernel {
        context: "renumbering".into(),
        source,
    }
}

/// The mean of an index distance (0 without edges).
pub(crate) fn mean(d: &IndexDistance) -> f64 {
    if d.edges == 0 {
        0.0
    } else {
        d.sum as f64 / d.edges as f64
    }
}

/// Whether `auto` renumbers a mesh of `n` nodes in `dim` dimensions whose mean index
/// distance is `mean`.
pub fn auto_renumbers(n: usize, dim: usize, mean: f64) -> bool {
    let scale = (n as f64).powf((dim as f64 - 1.0) / dim as f64);
    n >= AUTO_MIN_NODES && mean > AUTO_SPREAD * scale
}

/// Index distance across the cells' edges (each cell's own edges, so an edge shared by two
/// cells counts twice): no graph to build, so `auto` costs one pass over the cells on a mesh
/// it leaves alone. Measured in the cells' own numbering (after renumbering, on the
/// renumbered cells: sequential reads, no look-up per node).
pub(crate) fn cell_distance(cells: &CellList) -> IndexDistance {
    let mut d = IndexDistance::default();
    for (code, nodes) in cells.iter() {
        let Some(kind) = CellKind::from_vtk(code) else {
            continue;
        };
        for &[a, b] in kind.edges() {
            if let (Some(&x), Some(&y)) = (nodes.get(a as usize), nodes.get(b as usize)) {
                let gap = x.abs_diff(y);
                d.max = d.max.max(gap);
                d.sum = d.sum.saturating_add(u64::from(gap));
                d.edges += 1;
            }
        }
    }
    d
}

/// The permutation `how` asks for on this mesh (`None`: as given), and the report.
fn choose(
    how: Renumber,
    input: &MoveInput<'_>,
) -> Result<(Option<Order>, RenumberReport), CliError> {
    let n = input.points.len();
    let before = cell_distance(input.cells);
    let method = match how {
        Renumber::Auto if auto_renumbers(n, input.dim, mean(&before)) => Renumber::Rcm,
        Renumber::Auto => Renumber::Off,
        other => other,
    };
    let mut order = Order {
        order: vec![0; n],
        inverse: vec![0; n],
        graph: None,
    };
    let (o, i) = (&mut order.order, &mut order.inverse);
    match method {
        Renumber::Rcm => {
            let graph = edge_graph(&cells_view(input.cells, n)?, false)?;
            rcm_order(&graph.view()?, o, i).map_err(kernel)?;
            order.graph = Some(graph);
        }
        Renumber::Hilbert => {
            let mut keys = vec![0u64; n];
            if input.dim == 2 {
                hilbert_order(&points_d::<2>(input.points), o, i, &mut keys)
            } else {
                hilbert_order(&points_d::<3>(input.points), o, i, &mut keys)
            }
            .map_err(kernel)?;
        }
        Renumber::Off | Renumber::Auto => {}
    }
    // Renumbered, the distance after is measured on the renumbered cells (no second
    // pass of scattered look-ups); left alone, it is the distance before.
    let after = (method == Renumber::Off).then_some(before);
    let report = RenumberReport {
        method: match method {
            Renumber::Rcm => "rcm",
            Renumber::Hilbert => "hilbert",
            Renumber::Off | Renumber::Auto => "off",
        },
        mean_distance_before: Some(mean(&before)),
        mean_distance_after: after.as_ref().map(mean),
        bandwidth_before: Some(before.max),
        bandwidth_after: after.map(|a| a.max),
        seconds: 0.0,
    };
    Ok(((method != Renumber::Off).then_some(order), report))
}

/// A cell list with its node indices renumbered by `p`.
fn renumbered(list: &CellList, p: Permutation<'_>) -> Result<CellList, CliError> {
    let mut out = list.clone();
    deform_kernel::order::renumber(p, &mut out.nodes).map_err(kernel)?;
    Ok(out)
}

/// `run_move_in_steps`, on the mesh renumbered as `how` says; the result in the input's
/// numbering.
pub fn run_move_renumbered(
    input: &MoveInput<'_>,
    sliding: &[SlideMarker<'_>],
    steps: usize,
    how: Renumber,
) -> Result<(MoveResult, RenumberReport), CliError> {
    let t0 = Instant::now();
    let (order, mut report) = if how == Renumber::Off {
        (None, off_report())
    } else {
        choose(how, input)?
    };
    let Some(mut order) = order else {
        report.seconds = t0.elapsed().as_secs_f64();
        return Ok((run_move_in_steps(input, sliding, steps)?, report));
    };
    let input_graph = order.graph.take();
    let p = order.view()?;
    let mut points = vec![[0.0; 3]; input.points.len()];
    permute(p, input.points, &mut points).map_err(kernel)?;
    let cells = renumbered(input.cells, p)?;
    let after = cell_distance(&cells);
    report.mean_distance_after = Some(mean(&after));
    report.bandwidth_after = Some(after.max);
    let moved: Vec<CellList> = input
        .moved
        .iter()
        .map(|l| renumbered(l, p))
        .collect::<Result<_, _>>()?;
    let fixed: Vec<CellList> = input
        .fixed
        .iter()
        .map(|l| renumbered(l, p))
        .collect::<Result<_, _>>()?;
    let slides: Vec<CellList> = sliding
        .iter()
        .map(|s| renumbered(s.elements, p))
        .collect::<Result<_, _>>()?;
    let sliding: Vec<SlideMarker<'_>> = sliding
        .iter()
        .zip(&slides)
        .map(|(s, elements)| SlideMarker {
            name: s.name,
            elements,
        })
        .collect();
    let motion = match &input.motion {
        Motion::Field(list) => Motion::Field(renumbered_field(list, p)?),
        other => other.clone(),
    };
    // RCM's graph, renumbered: the graph the renumbered cells give (rows sorted as built).
    let graph = match &input_graph {
        Some(g) => Some(permuted_symmetric(p, &g.view()?)?),
        None => None,
    };
    let renumbered_input = MoveInput {
        points: &points,
        cells: &cells,
        moved: moved.iter().collect(),
        fixed: fixed.iter().collect(),
        motion,
        graph: graph.as_ref(),
        ..*input
    };
    let spent = t0.elapsed();
    let mut result = run_move_in_steps(&renumbered_input, &sliding, steps)?;
    let t1 = Instant::now();
    for field in [&mut result.deformed, &mut result.displacement] {
        let mut back = vec![[0.0; 3]; field.len()];
        permute(p.inverted(), field, &mut back).map_err(kernel)?;
        *field = back;
    }
    report.seconds = (spent + t1.elapsed()).as_secs_f64();
    // The graph in the input's numbering, for the quality pass.
    result.graph = input_graph;
    Ok((result, report))
}

/// The symmetric graph `g` (as [`edge_graph`] builds every mesh graph) in the new numbering:
/// what the kernel's `permute_graph` writes (row `new` holds the new indices of old row
/// `order[new]`'s neighbours, ascending), without sorting any row. The new rows are visited
/// in order and each is appended to the rows of its neighbours, so every row fills in
/// ascending order; on an RCM order those writes stay within the band. Only for symmetric
/// graphs (on others it would list in-neighbours): a graph whose rows do not fill exactly
/// goes to `permute_graph` instead, which catches most but not every non-symmetric graph.
fn permuted_symmetric(p: Permutation<'_>, g: &Graph<'_>) -> Result<OwnedGraph, CliError> {
    let (order, inverse) = (p.order(), p.inverse());
    let mut offsets = Vec::with_capacity(order.len() + 1);
    let mut at = 0u32;
    offsets.push(at);
    for &old in order {
        at += g.neighbors(old as usize).len() as u32;
        offsets.push(at);
    }
    let mut cursor = offsets.clone();
    let mut targets = vec![0u32; g.edge_count()];
    let mut filled = true;
    for (new, &old) in order.iter().enumerate() {
        for &t in g.neighbors(old as usize) {
            let row = inverse.get(t as usize).map_or(0, |&r| r as usize);
            let (Some(c), Some(&end)) = (cursor.get_mut(row), offsets.get(row + 1)) else {
                continue;
            };
            match targets.get_mut(*c as usize).filter(|_| *c < end) {
                Some(slot) => *slot = new as u32,
                None => filled = false,
            }
            *c += 1;
        }
    }
    let exact = cursor
        .iter()
        .zip(offsets.iter().skip(1))
        .all(|(c, o)| c == o);
    if filled && exact {
        return Ok(OwnedGraph { offsets, targets });
    }
    let mut out = OwnedGraph {
        offsets: vec![0; g.node_count() + 1],
        targets: vec![0; g.edge_count()],
    };
    permute_graph(p, g, &mut out.offsets, &mut out.targets, None).map_err(kernel)?;
    Ok(out)
}

/// A per-node displacement list in the new numbering, ascending by node as the engine
/// expects.
fn renumbered_field(
    list: &[(u32, [f64; 3])],
    p: Permutation<'_>,
) -> Result<Vec<(u32, [f64; 3])>, CliError> {
    let mut nodes: Vec<u32> = list.iter().map(|(n, _)| *n).collect();
    deform_kernel::order::renumber(p, &mut nodes).map_err(kernel)?;
    let mut out: Vec<(u32, [f64; 3])> = nodes
        .into_iter()
        .zip(list.iter().map(|(_, d)| *d))
        .collect();
    out.sort_by_key(|(n, _)| *n);
    Ok(out)
}

/// The report of a run in the input's numbering (nothing measured).
pub(crate) fn off_report() -> RenumberReport {
    RenumberReport {
        method: "off",
        mean_distance_before: None,
        mean_distance_after: None,
        bandwidth_before: None,
        bandwidth_after: None,
        seconds: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `order[new] = old` from a seeded shuffle, and its inverse.
    fn shuffled(n: usize, mut state: u64) -> (Vec<u32>, Vec<u32>) {
        let mut order: Vec<u32> = (0..n as u32).collect();
        for i in (1..n).rev() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            order.swap(i, (state % (i as u64 + 1)) as usize);
        }
        let mut inverse = vec![0u32; n];
        for (k, &v) in order.iter().enumerate() {
            inverse[v as usize] = k as u32;
        }
        (order, inverse)
    }

    /// The kernel's `permute_graph` of `g`.
    fn kernel_permuted(p: Permutation<'_>, g: &Graph<'_>) -> OwnedGraph {
        let mut out = OwnedGraph {
            offsets: vec![0; g.node_count() + 1],
            targets: vec![0; g.edge_count()],
        };
        permute_graph(p, g, &mut out.offsets, &mut out.targets, None).unwrap();
        out
    }

    /// On a mesh graph (symmetric) the row-sort-free permutation writes the kernel's bits;
    /// on a non-symmetric graph it falls back to the kernel.
    #[test]
    fn permuted_symmetric_is_the_kernels_permute_graph() {
        // Tetrahedra of a 4 x 4 x 4 lattice of points split along one diagonal each.
        let mut cells = CellList::new();
        let at = |x: u32, y: u32, z: u32| x + 4 * y + 16 * z;
        for (x, y, z) in (0..27u32).map(|c| (c % 3, c / 3 % 3, c / 9)) {
            let [a, b, c, d] = [
                at(x, y, z),
                at(x + 1, y, z),
                at(x, y + 1, z),
                at(x, y, z + 1),
            ];
            let e = at(x + 1, y + 1, z + 1);
            for tet in [[a, b, c, d], [b, c, d, e]] {
                assert!(cells.push(CellKind::Tetra, &tet));
            }
        }
        let mesh = edge_graph(&cells_view(&cells, 64).unwrap(), false).unwrap();
        // Out-degrees 2, 0, 1 and in-degrees 1, 1, 1: the rows cannot fill.
        let directed = OwnedGraph {
            offsets: vec![0, 2, 2, 3],
            targets: vec![1, 2, 0],
        };
        for seed in 1..20u64 {
            for g in [&mesh, &directed] {
                let g = g.view().unwrap();
                let (order, inverse) = shuffled(g.node_count(), seed * 0x9e37_79b9);
                let p = Permutation::new(&order, &inverse).unwrap();
                let (got, want) = (permuted_symmetric(p, &g).unwrap(), kernel_permuted(p, &g));
                assert_eq!(got.offsets, want.offsets);
                assert_eq!(got.targets, want.targets);
            }
        }
    }
}
