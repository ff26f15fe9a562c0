//! The whole-mesh spring arrays the checks and the benchmark build for their serial (and
//! replicated) reference: graph, Batina stiffness and boundary mask, and the boundary
//! displacement of the checks.

use deform_kernel::spring::{batina_stiffness, SpringSystem};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::Mesh;

/// A whole mesh's spring arrays.
pub struct WholeSprings {
    /// CSR offsets of the edge graph.
    pub offsets: Vec<u32>,
    /// CSR targets (rows sorted by node number).
    pub targets: Vec<u32>,
    /// Batina stiffness (`p = 1`) per directed edge.
    pub stiffness: Vec<f64>,
    /// The mesh's boundary mask.
    pub fixed: Vec<u8>,
}

impl WholeSprings {
    /// The arrays of `mesh` (panics on an invalid mesh: checks and benchmarks only).
    pub fn new<const D: usize>(mesh: &Mesh<D>) -> Self {
        let n = mesh.node_count();
        let cells = mesh.cells().expect("cells");
        let mut offsets = vec![0u32; n + 1];
        let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
        let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).expect("graph");
        targets.truncate(used);
        let mut stiffness = vec![0.0f64; used];
        let g = Graph::new(&offsets, &targets).expect("graph");
        batina_stiffness(&g, &mesh.points, 1.0, &mut stiffness).expect("stiffness");
        WholeSprings {
            offsets,
            targets,
            stiffness,
            fixed: mesh.boundary_mask(),
        }
    }

    /// The validated system.
    pub fn system(&self) -> SpringSystem<'_, f64> {
        let g = Graph::new(&self.offsets, &self.targets).expect("graph");
        let mut scratch = vec![0u32; g.node_count()];
        SpringSystem::new(g, &self.stiffness, &self.fixed, &mut scratch).expect("system")
    }
}

/// The checks' boundary displacement: a small rotation plus a shear at fixed nodes, zero at
/// free ones.
pub fn boundary_values<const D: usize>(mesh: &Mesh<D>, fixed: &[u8]) -> Vec<[f64; D]> {
    mesh.points
        .iter()
        .zip(fixed)
        .map(|(p, &f)| {
            let mut d = [0.0; D];
            if f != 0 {
                d[0] = -0.05 * p[1] + 0.01 * p[0] * p[1];
                d[1] = 0.05 * p[0];
                if D == 3 {
                    d[D - 1] = 0.02 * p[0];
                }
            }
            d
        })
        .collect()
}

/// Sums `groups` over the processes in one call of `sum_words` (their words packed).
pub(crate) fn sum_exact_packed(
    groups: &mut [&mut [deform_kernel::exact_sum::ExactSum]],
    sum_words: impl FnOnce(&mut [i64]),
) {
    use deform_kernel::exact_sum::{ExactSum, EXACT_SUM_WORDS};
    let mut words: Vec<i64> = groups
        .iter()
        .flat_map(|g| g.iter())
        .flat_map(|s| s.to_words())
        .collect();
    sum_words(&mut words);
    for (s, w) in groups
        .iter_mut()
        .flat_map(|g| g.iter_mut())
        .zip(words.chunks_exact(EXACT_SUM_WORDS))
    {
        let mut a = [0i64; EXACT_SUM_WORDS];
        a.copy_from_slice(w);
        *s = ExactSum::from_words(a);
    }
}
