//! Shared set-up for the spring tests: builds kernel systems and reference nets from the same
//! mesh data.
#![allow(dead_code)]

use deform_host_tests::spring_ref::{self, Net};
use deform_kernel::spring::{
    batina_stiffness, AmgHierarchy, AmgOptions, AmgSizes, AngleSystem, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph, Real};
use deform_meshgen::{naca_triangulated, rotate_markers2, AirfoilGrid};

/// Mesh data owned by a test: CSR graph, stiffness, fixed mask, points.
pub struct Case<T, const D: usize> {
    pub offsets: Vec<u32>,
    pub targets: Vec<u32>,
    pub k: Vec<T>,
    pub fixed: Vec<u8>,
    pub points: Vec<[T; D]>,
}

impl<T: Real, const D: usize> Case<T, D> {
    /// Builds the case from points and undirected edges (reference CSR builder; kernel
    /// stiffness with exponent 1).
    pub fn new(points: &[[f64; D]], edges: &[[u32; 2]], fixed: Vec<u8>) -> Self {
        let (offsets, targets) = spring_ref::csr(points.len(), edges);
        let points: Vec<[T; D]> = points.iter().map(|p| p.map(T::from_f64)).collect();
        let mut k = vec![T::ZERO; targets.len()];
        {
            let g = Graph::new(&offsets, &targets).unwrap();
            batina_stiffness(&g, &points, T::ONE, &mut k).unwrap();
        }
        Case {
            offsets,
            targets,
            k,
            fixed,
            points,
        }
    }

    pub fn n(&self) -> usize {
        self.points.len()
    }

    pub fn graph(&self) -> Graph<'_> {
        Graph::new(&self.offsets, &self.targets).unwrap()
    }

    pub fn system(&self) -> SpringSystem<'_, T> {
        let mut scratch = vec![0u32; SpringSystem::<T>::scratch_len(self.n())];
        SpringSystem::new(self.graph(), &self.k, &self.fixed, &mut scratch).unwrap()
    }

    pub fn angle(&self, eps: f64) -> AngleSystem<'_, T, D> {
        AngleSystem::new(self.system(), &self.points, T::from_f64(eps)).unwrap()
    }

    /// The reference net with the same stiffness bits (converted to `F`).
    pub fn net<F: spring_ref::Float>(&self) -> Net<F> {
        Net {
            offsets: self.offsets.clone(),
            targets: self.targets.clone(),
            k: self.k.iter().map(|k| F::of(k.to_f64())).collect(),
            fixed: self.fixed.clone(),
        }
    }

    pub fn points_f64(&self) -> Vec<[f64; D]> {
        self.points.iter().map(|p| p.map(|x| x.to_f64())).collect()
    }
}

/// Small graded annulus (inner radius 1, outer 4), both rings fixed.
pub fn annulus<T: Real>(nr: usize, nt: usize) -> Case<T, 2> {
    let (p, e, f) = spring_ref::annulus(nr, nt, 1.0, 4.0, 1.2);
    Case::new(&p, &e, f)
}

/// Small sheared 3D block, boundary fixed.
pub fn cube<T: Real>(n: usize) -> Case<T, 3> {
    let (p, e, f) = spring_ref::cube(n);
    Case::new(&p, &e, f)
}

/// Deterministic pseudo-random numbers in [-1, 1) (a simple LCG; test data only).
pub struct Lcg(pub u64);

impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A value field: fixed nodes get `f(point, component)`-style data from the generator, free
/// nodes get `free` (or random values when `None`).
pub fn field<T: Real, const D: usize, const V: usize>(
    case: &Case<T, D>,
    rng: &mut Lcg,
    free: Option<f64>,
) -> Vec<[T; V]> {
    (0..case.n())
        .map(|i| {
            let mut v = [T::ZERO; V];
            for x in v.iter_mut() {
                let r = rng.next();
                *x = T::from_f64(if case.fixed[i] != 0 {
                    r
                } else {
                    free.unwrap_or(r)
                });
            }
            v
        })
        .collect()
}

/// Rotation by `deg` about the origin on the inner ring (|p| < 1.5), zero elsewhere.
pub fn inner_rotation<T: Real>(case: &Case<T, 2>, deg: f64) -> Vec<[T; 2]> {
    (0..case.n())
        .map(|i| {
            let p = case.points[i].map(|x| x.to_f64());
            if case.fixed[i] != 0 && (p[0] * p[0] + p[1] * p[1]).sqrt() < 1.5 {
                spring_ref::rotation_displacement(p, [0.0, 0.0], deg).map(T::from_f64)
            } else {
                [T::ZERO; 2]
            }
        })
        .collect()
}

/// `Vec<[T; V]>` to `Vec<Vec<F>>` for the reference.
pub fn to_ref<T: Real, F: spring_ref::Float, const V: usize>(x: &[[T; V]]) -> Vec<Vec<F>> {
    x.iter()
        .map(|v| v.iter().map(|c| F::of(c.to_f64())).collect())
        .collect()
}

/// Bit patterns of a field.
pub fn bits<T: Real, const V: usize>(x: &[[T; V]]) -> Vec<u64> {
    x.iter()
        .flat_map(|v| v.iter().map(|c| c.to_bits_u64()))
        .collect()
}

/// Owned buffers of a multigrid hierarchy for a system, sized by the two-phase query.
pub struct AmgBuffers<T> {
    pub work: Vec<u32>,
    pub index: Vec<u32>,
    pub values: Vec<T>,
    pub sizes: AmgSizes,
}

impl<T: Real> AmgBuffers<T> {
    pub fn new(sys: &SpringSystem<'_, T>, opts: &AmgOptions<T>) -> Self {
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(sys)];
        let sizes = AmgHierarchy::setup_len(sys, opts, &mut work).unwrap();
        AmgBuffers {
            work,
            index: vec![0; sizes.index],
            values: vec![T::ZERO; sizes.values],
            sizes,
        }
    }

    /// The hierarchy of `sys` in these buffers.
    pub fn build<'h>(
        &'h mut self,
        sys: &SpringSystem<'_, T>,
        opts: &AmgOptions<T>,
    ) -> AmgHierarchy<'h, T> {
        AmgHierarchy::setup(sys, opts, &mut self.work, &mut self.index, &mut self.values).unwrap()
    }
}

/// Kernel system of a meshgen NACA 2412 mesh, with the airfoil rotated 10° (`x0`: the wall
/// displacements on the fixed nodes, zero elsewhere).
pub struct Naca {
    pub offsets: Vec<u32>,
    pub targets: Vec<u32>,
    pub k: Vec<f64>,
    pub fixed: Vec<u8>,
    pub points: Vec<[f64; 2]>,
    pub x0: Vec<[f64; 2]>,
}

pub fn naca(grid: &AirfoilGrid) -> Naca {
    let mesh = naca_triangulated(grid).unwrap();
    let n = mesh.node_count();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    let mut k = vec![0.0; used];
    batina_stiffness(
        &Graph::new(&offsets, &targets).unwrap(),
        &mesh.points,
        1.0,
        &mut k,
    )
    .unwrap();
    let rot = rotate_markers2(&mesh, &["airfoil"], AirfoilGrid::quarter_chord(), 10.0).unwrap();
    Naca {
        offsets,
        targets,
        k,
        fixed: mesh.boundary_mask(),
        points: mesh.points.clone(),
        x0: rot.to_field(n),
    }
}
