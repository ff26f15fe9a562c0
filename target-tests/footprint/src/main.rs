//! Footprint of deform-kernel on a Cortex-M4F (QEMU mps2-an386), inside **64 KiB of RAM**.
//!
//! `memory.x` gives the linker 64 KiB of RAM: statics (`.data` + `.bss`, which hold the
//! caller's buffers of the big run) at the bottom, the stack at the top. The program
//!
//! 1. deforms a 960-node 2D structured mesh (40 × 24, f32) with the quaternion method
//!    (`deform_idw` and `deform_tfi`), its bottom wall turned by 2°, and checks the result
//!    (every boundary node bit-exact, every grid line still monotone);
//! 2. paints the free stack with a pattern before each main entry point and scans for the
//!    lowest overwritten word afterwards: the **peak stack** of that call, printed per entry
//!    point (f32 and f64). The solvers' results are checked too: the multigrid entry points
//!    (hierarchy symbolic pass and setup, `solve_linear_amg`, `solve_angle_amg`) run on the
//!    20-node spring system of the other spring entries (a two-level hierarchy, or the run
//!    fails) and must converge and agree with the one-level CG;
//! 3. prints static RAM + deepest stack seen, and fails (exit 1) if that exceeds 64 KiB or
//!    the pattern was used up (a stack overflow into the statics).
//!
//! Stack painting needs raw memory access, the only `unsafe` in the on-target code; it is
//! confined to the `stack` module and the one `&'static mut` to the big buffers.
#![no_std]
#![no_main]
#![allow(unsafe_code)]

use core::hint::black_box;
use deform_kernel::Direction;
use deform_kernel::Directions;

use cortex_m as _; // critical-section implementation
use cortex_m_rt::entry;
use defmt_semihosting as _; // global defmt logger

use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, deform_spring, deform_spring_scratch_len, deform_tfi,
    deform_tfi_scratch_len, propagate_spring_scratch_len, BoundaryMotion, RotationSource,
};
#[cfg(not(feature = "micromath"))]
use deform_kernel::spring::batina_stiffness;
use deform_kernel::spring::{
    solve_linear_amg_scratch_len, solve_linear_scratch_len, AmgHierarchy, AmgOptions, AmgSizes,
    AngleMethod, AngleSystem, LinearMethod, Preconditioner, SolveOptions, SolveReport,
    SpringSystem,
};
use deform_kernel::taubin::{
    smooth_arclength, smooth_arclength_scratch_len, smooth_graph, smooth_structured, GraphOptions,
    SmoothOptions, StructuredOptions, TaubinParams,
};
use deform_kernel::{graph_from_cells, Block, Cells, Error, Graph, Quat, Real};

/// Any panic ends QEMU with exit status 1.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    defmt::error!("footprint: panic");
    semihosting::process::exit(1)
}

/// A failed check: log and exit 1.
fn fail(what: &str) -> ! {
    defmt::error!("footprint: FAILED: {=str}", what);
    semihosting::process::exit(1)
}

/// Logs a kernel error (through `defmt::Format` when the kernel's `defmt` feature is on).
fn kernel_error(what: &str, _e: Error) -> ! {
    #[cfg(feature = "kernel-defmt")]
    defmt::error!("footprint: {=str}: {}", what, _e);
    fail(what)
}

/// RAM the linker script gives the program.
const RAM_BYTES: usize = 64 * 1024;

// ---------------------------------------------------------------------------------------------
// Stack painting

mod stack {
    use core::ptr;

    const PATTERN: u32 = 0xA5C3_5A3C;

    extern "C" {
        /// End of `.bss`/`.uninit` (cortex-m-rt): the lowest address the stack may reach.
        static __sheap: u32;
        /// Top of RAM, the initial stack pointer (cortex-m-rt).
        static _stack_start: u32;
    }

    /// Lowest address of the stack area (end of the statics).
    pub fn bottom() -> usize {
        // Only the address of the linker symbol is taken, never its value.
        ptr::addr_of!(__sheap) as usize
    }

    /// Highest address (exclusive) of the stack area.
    pub fn top() -> usize {
        ptr::addr_of!(_stack_start) as usize
    }

    /// Fills the free stack (from the end of the statics to just below the current stack
    /// pointer) with the pattern.
    #[inline(never)]
    pub fn paint() {
        let sp = cortex_m::register::msp::read() as usize;
        let end = (sp - 16) & !3;
        let mut p = (bottom() + 3) & !3;
        while p < end {
            // SAFETY: [bottom, sp − 16) is RAM below the live stack frames and above the
            // statics; nothing else uses it (no interrupts are enabled), and a leaf function
            // with no stack use below its own frame writes it.
            unsafe { ptr::write_volatile(p as *mut u32, PATTERN) };
            p += 4;
        }
    }

    /// Lowest address whose word no longer holds the pattern (the deepest stack use since the
    /// last [`paint`]); `bottom()` when the whole area was used (overflow).
    pub fn lowest_used() -> usize {
        let mut p = (bottom() + 3) & !3;
        // SAFETY: reads of RAM words in [bottom, top).
        while p < top() && unsafe { ptr::read_volatile(p as *const u32) } == PATTERN {
            p += 4;
        }
        p
    }
}

/// Calls `f` in a frame of its own, below the caller's.
#[inline(never)]
fn below<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// Measures the peak stack of calls and remembers the deepest point reached.
struct Meter {
    /// Largest `top − lowest used address` seen (bytes of stack in use at the deepest point,
    /// including `main`'s frame).
    peak_depth: usize,
    /// Set when a measurement found the pattern used up.
    overflow: bool,
}

impl Meter {
    /// Runs `f` on a freshly painted stack and prints the bytes it used below the caller's
    /// stack pointer. `f` runs behind a non-inlined call ([`below`]), so everything the
    /// kernel routine keeps on the stack is below that pointer and counted, whatever the
    /// optimiser inlines into `f` (inlined into the caller, its locals would sit in the
    /// caller's frame and the figure would change with unrelated code).
    fn measure<R>(&mut self, name: &str, f: impl FnOnce() -> R) -> R {
        let sp = self.start();
        let r = below(f);
        // The result stays in place (a hierarchy is kilobytes; `black_box(r)` would copy it).
        black_box(&r);
        self.finish(name, sp);
        r
    }

    /// Paints the free stack and returns the caller's stack pointer: the first half of
    /// [`Meter::measure`], for a call whose large result must land in the caller's frame
    /// without a copy (a direct call of a non-inlined function between `start` and `finish`).
    #[inline(always)]
    fn start(&mut self) -> usize {
        stack::paint();
        cortex_m::register::msp::read() as usize
    }

    /// Scans the painted stack after the call, prints the bytes used below `sp` and records the
    /// depth: the second half of [`Meter::measure`].
    #[inline(always)]
    fn finish(&mut self, name: &str, sp: usize) {
        let low = stack::lowest_used();
        if low <= (stack::bottom() + 3) & !3 {
            self.overflow = true;
        }
        let depth = stack::top() - low;
        self.peak_depth = self.peak_depth.max(depth);
        defmt::println!(
            "stack {=str}: {=usize} bytes (depth from top of RAM {=usize})",
            name,
            sp.saturating_sub(low),
            depth
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The 960-node problem, in static buffers (the caller's memory)
//
// It was 1,000 nodes (40 × 25) until the multigrid entries came: the f64 hierarchy setup needs
// about 15 KB of stack depth (the 3 KB hierarchy value, 7 KB of the kernel's setup, its work
// buffer, the small system), 950 bytes more than the 1,000-node statics (51,544 bytes) left.

const NI: usize = 40;
const NJ: usize = 24;
const N: usize = NI * NJ;
/// Perimeter nodes.
const NB: usize = 2 * (NI + NJ) - 4;

/// Every buffer of the 960-node run.
struct Big {
    points: [[f32; 2]; N],
    translations: [[f32; 2]; N],
    rotations: [Quat<f32>; N],
    /// `max(deform_idw_scratch_len, deform_tfi_scratch_len, smooth_arclength_scratch_len)`.
    scratch: [f32; 2 * N],
    out: [[f32; 2]; N],
    nodes: [u32; NB],
    deformed: [[f32; 2]; NB],
    node_rotations: [Quat<f32>; NB],
}

const ZQ: Quat<f32> = Quat::new(0.0, 0.0, 0.0, 0.0);

static mut BIG: Big = Big {
    points: [[0.0; 2]; N],
    translations: [[0.0; 2]; N],
    rotations: [ZQ; N],
    scratch: [0.0; 2 * N],
    out: [[0.0; 2]; N],
    nodes: [0; NB],
    deformed: [[0.0; 2]; NB],
    node_rotations: [ZQ; NB],
};

/// Builds the grid (unit spacing) and the motion: the bottom wall (j = 0) turns by 2° about its
/// midpoint, the rest of the perimeter stays.
fn build_big(b: &mut Big) {
    for (p, pt) in b.points.iter_mut().enumerate() {
        *pt = [(p % NI) as f32, (p / NI) as f32];
    }
    let q = Quat::from_rotation_z(2f32.to_radians());
    let c = [(NI - 1) as f32 * 0.5, 0.0];
    let mut k = 0;
    for p in 0..N {
        let (i, j) = (p % NI, p / NI);
        if i == 0 || j == 0 || i == NI - 1 || j == NJ - 1 {
            let pt = b.points.get(p).copied().unwrap_or_default();
            let (d, r) = if j == 0 {
                let v = q.rotate_2d([pt[0] - c[0], pt[1] - c[1]]);
                ([v[0] + c[0], v[1] + c[1]], q)
            } else {
                (pt, Quat::identity())
            };
            if let (Some(n), Some(dd), Some(rr)) = (
                b.nodes.get_mut(k),
                b.deformed.get_mut(k),
                b.node_rotations.get_mut(k),
            ) {
                *n = p as u32;
                *dd = d;
                *rr = r;
            }
            k += 1;
        }
    }
}

/// Checks the deformed grid: boundary bits exact, finite, every i-line increasing in x and
/// every j-line increasing in y (no fold).
fn check_big(b: &Big, what: &str) {
    for (&n, d) in b.nodes.iter().zip(&b.deformed) {
        let o = b.out.get(n as usize).copied().unwrap_or_default();
        if o[0].to_bits() != d[0].to_bits() || o[1].to_bits() != d[1].to_bits() {
            fail(what);
        }
    }
    for p in 0..N {
        let o = b.out.get(p).copied().unwrap_or_default();
        if !(o[0].is_finite() && o[1].is_finite()) {
            fail(what);
        }
        if p % NI + 1 < NI && b.out.get(p + 1).is_some_and(|r| r[0] <= o[0]) {
            fail(what);
        }
        if p + NI < N && b.out.get(p + NI).is_some_and(|u| u[1] <= o[1]) {
            fail(what);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Small problems for the other entry points (20-node triangle mesh)

const SX: usize = 5;
const SY: usize = 4;
const SN: usize = SX * SY;
const ST: usize = 2 * (SX - 1) * (SY - 1);
/// `targets` capacity the graph builder needs (`graph_from_cells_len`: 6 per triangle).
const SE: usize = 6 * ST;
/// Directed edges of the small mesh's graph: horizontal, vertical and diagonal springs, both
/// ways (the stiffness has exactly this many entries).
const SE_USED: usize = 2 * ((SX - 1) * SY + SX * (SY - 1) + (SX - 1) * (SY - 1));
const SB: usize = 2 * (SX + SY) - 4;

/// The small mesh's nodes, graph and boundary (the triangles are built, turned into the graph
/// and dropped in [`small`]: they would only take stack in the callers).
struct Small<T> {
    points: [[T; 2]; SN],
    graph_offsets: [u32; SN + 1],
    targets: [u32; SE],
    used: usize,
    fixed: [u8; SN],
    boundary: [u32; SB],
}

fn small<T: Real>() -> Small<T> {
    let mut offsets = [0u32; ST + 1];
    let mut nodes = [0u32; 3 * ST];
    let kinds = [5u8; ST];
    let mut m = Small {
        points: [[T::ZERO; 2]; SN],
        graph_offsets: [0; SN + 1],
        targets: [0; SE],
        used: 0,
        fixed: [0; SN],
        boundary: [0; SB],
    };
    let mut b = 0;
    for p in 0..SN {
        let (i, j) = (p % SX, p / SX);
        let edge = i == 0 || j == 0 || i == SX - 1 || j == SY - 1;
        let jit = if edge {
            0.0
        } else {
            ((i * 7 + j * 13) % 5) as f64 * 0.05 - 0.1
        };
        if let Some(pt) = m.points.get_mut(p) {
            *pt = [
                T::from_f64(i as f64 + jit),
                T::from_f64(j as f64 * 0.8 - jit),
            ];
        }
        if edge {
            if let (Some(f), Some(s)) = (m.fixed.get_mut(p), m.boundary.get_mut(b)) {
                *f = 1;
                *s = p as u32;
            }
            b += 1;
        }
    }
    let mut c = 0;
    for j in 0..SY - 1 {
        for i in 0..SX - 1 {
            let a = (i + SX * j) as u32;
            let (b1, c1, d1) = (a + 1, a + 1 + SX as u32, a + SX as u32);
            for t in [[a, b1, c1], [a, c1, d1]] {
                for (k, v) in t.into_iter().enumerate() {
                    if let Some(s) = nodes.get_mut(3 * c + k) {
                        *s = v;
                    }
                }
                c += 1;
                if let Some(o) = offsets.get_mut(c) {
                    *o = 3 * c as u32;
                }
            }
        }
    }
    match Cells::new(SN, &offsets, &nodes, &kinds)
        .and_then(|cells| graph_from_cells(&cells, false, &mut m.graph_offsets, &mut m.targets))
    {
        Ok(used) => m.used = used,
        Err(e) => kernel_error("small mesh", e),
    }
    m
}

/// Quaternion algebra: construction, products, rotation, normalisation, interpolation.
#[inline(never)]
fn quat_ops<T: Real>() -> T {
    let a = Quat::from_axis_angle(
        black_box([T::ONE, T::TWO, T::from_f64(-0.5)]),
        black_box(T::from_f64(0.7)),
    )
    .unwrap_or(Quat::identity());
    let b = Quat::rotation_arc(
        black_box([T::ONE, T::ZERO, T::ZERO]),
        black_box([T::ZERO, T::ONE, T::ONE]),
    )
    .unwrap_or(Quat::identity());
    let c = (a * b).normalize().unwrap_or(Quat::identity());
    let s = Quat::slerp(a, c, T::from_f64(0.3)).unwrap_or(Quat::identity());
    let v = s.rotate(black_box([T::from_f64(0.3), T::ONE, T::TWO]));
    #[cfg(feature = "micromath")]
    let v = {
        let f = s.normalize_fast().unwrap_or(Quat::identity());
        let w = f.rotate(v);
        [v[0] + w[0], v[1] + w[1], v[2] + w[2]]
    };
    v[0] + v[1] + v[2]
}

/// The spring system of the small mesh, then `f` on it.
fn with_system<T: Real, R>(m: &Small<T>, f: impl FnOnce(&SpringSystem<'_, T>) -> R) -> R {
    let targets = m.targets.get(..m.used).unwrap_or(&[]);
    let g = match Graph::new(&m.graph_offsets, targets) {
        Ok(g) => g,
        Err(e) => kernel_error("graph", e),
    };
    let mut k = [T::ZERO; SE_USED];
    let k = k.get_mut(..m.used).unwrap_or(&mut []);
    // With `micromath`, the fast stiffness (so the size table shows that feature's code).
    #[cfg(feature = "micromath")]
    let r = deform_kernel::spring::batina_stiffness_fast(&g, &m.points, T::ONE, k);
    #[cfg(not(feature = "micromath"))]
    let r = batina_stiffness(&g, &m.points, T::ONE, k);
    if let Err(e) = r {
        kernel_error("stiffness", e);
    }
    let k: &[T] = k;
    let mut seen = [0u32; SN];
    match SpringSystem::new(g, k, &m.fixed, &mut seen) {
        Ok(sys) => f(&sys),
        Err(e) => kernel_error("spring system", e),
    }
}

/// Boundary data for the small mesh: the bottom row lifted by a bump, zero elsewhere.
fn small_values<T: Real, const V: usize>() -> [[T; V]; SN] {
    let mut v = [[T::ZERO; V]; SN];
    for (i, x) in v.iter_mut().take(SX).enumerate() {
        for c in x.iter_mut() {
            *c = T::from_f64(0.1 * (i * (SX - 1 - i)) as f64);
        }
    }
    v
}

/// `"<name> f32"` or `"<name> f64"`.
fn tagged<T: Real>(f32_name: &'static str, f64_name: &'static str) -> &'static str {
    if T::MANTISSA_DIGITS == 24 {
        f32_name
    } else {
        f64_name
    }
}

/// Each small entry point runs in its own non-inlined function, so only its own mesh and
/// buffers are on the stack while it runs (the 64 KiB budget has about 15.6 KiB of stack next
/// to the 960-node statics).
#[inline(never)]
fn linear_cg<T: Real>(meter: &mut Meter) {
    let m = small::<T>();
    with_system(&m, |sys| {
        let mut values = small_values::<T, 2>();
        let mut scratch = [[T::ZERO; 2]; 5 * SN];
        let method = LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor {
                omega: T::from_f64(1.2),
            },
        };
        let opts = SolveOptions::default();
        let name = tagged::<T>("solve_linear CG-SSOR f32", "solve_linear CG-SSOR f64");
        let r = meter.measure(name, || {
            sys.solve_linear(&mut values, method, &opts, &mut scratch)
        });
        if !r.is_ok_and(|r| r.converged) {
            fail(name);
        }
    });
}

#[inline(never)]
fn linear_gs<T: Real>(meter: &mut Meter) {
    let m = small::<T>();
    with_system(&m, |sys| {
        let mut values = small_values::<T, 2>();
        let opts = SolveOptions::default();
        let name = tagged::<T>(
            "solve_linear Gauss-Seidel f32",
            "solve_linear Gauss-Seidel f64",
        );
        let r = meter.measure(name, || {
            sys.solve_linear(&mut values, LinearMethod::GaussSeidel, &opts, &mut [])
        });
        if !r.is_ok_and(|r| r.converged) {
            fail(name);
        }
    });
}

#[inline(never)]
fn angle_cg<T: Real>(meter: &mut Meter) {
    let m = small::<T>();
    with_system(&m, |sys| {
        let asys = match AngleSystem::new(*sys, &m.points, T::from_f64(0.01)) {
            Ok(a) => a,
            Err(e) => kernel_error("angle system", e),
        };
        let mut values = small_values::<T, 2>();
        let mut scratch = [[T::ZERO; 2]; 4 * SN];
        let opts = SolveOptions::default();
        let name = tagged::<T>("solve_angle CG f32", "solve_angle CG f64");
        let r = meter.measure(name, || {
            asys.solve_angle(&mut values, AngleMethod::Cg, &opts, &mut scratch)
        });
        if !r.is_ok_and(|r| r.converged) {
            fail(name);
        }
    });
}

#[inline(never)]
fn spring_deformation<T: Real>(meter: &mut Meter) {
    let m = small::<T>();
    with_system(&m, |sys| {
        let lift = small_values::<T, 1>();
        let mut deformed = [[T::ZERO; 2]; SB];
        for (d, &b) in deformed.iter_mut().zip(&m.boundary) {
            let p = m.points.get(b as usize).copied().unwrap_or([T::ZERO; 2]);
            let l = lift.get(b as usize).map_or(T::ZERO, |l| l[0]);
            *d = [p[0], p[1] + l];
        }
        let motion = BoundaryMotion {
            nodes: &m.boundary,
            deformed: &deformed,
            elements: None,
            rotations: RotationSource::Rigid(Quat::identity()),
            origin: None,
        };
        // Gauss–Seidel: no solver scratch, so `values` is only N items of 6 scalars (CG needs 6 N items).
        let method = LinearMethod::GaussSeidel;
        let mut t = [[T::ZERO; 2]; SN];
        let mut q = [Quat::identity(); SN];
        let mut s = [T::ZERO; 3 * SB];
        let mut v = [T::ZERO; 6 * SN];
        let mut out = [[T::ZERO; 2]; SN];
        let slen = deform_spring_scratch_len::<2>(SN, SB).min(s.len());
        let vlen = propagate_spring_scratch_len::<2>(&method, SN).min(v.len());
        let opts = SolveOptions::default();
        let name = tagged::<T>(
            "deform_spring (20 nodes) f32",
            "deform_spring (20 nodes) f64",
        );
        let r = meter.measure(name, || {
            deform_spring(
                &m.points,
                &motion,
                sys,
                method,
                &opts,
                &mut t,
                &mut q,
                s.get_mut(..slen).unwrap_or(&mut []),
                v.get_mut(..vlen).unwrap_or(&mut []),
                &mut out,
            )
        });
        match r {
            Ok((_, r)) if r.converged => {}
            Ok(_) => fail("deform_spring did not converge"),
            Err(e) => kernel_error("deform_spring", e),
        }
    });
}

#[inline(never)]
fn graph_smoothing<T: Real>(meter: &mut Meter) {
    let m = small::<T>();
    let targets = m.targets.get(..m.used).unwrap_or(&[]);
    let g = match Graph::new(&m.graph_offsets, targets) {
        Ok(g) => g,
        Err(e) => kernel_error("graph", e),
    };
    let mut values = m.points;
    let mut scratch = [[T::ZERO; 2]; SN];
    let gopts = GraphOptions {
        weights: None,
        fixed: Some(&m.fixed),
    };
    let name = tagged::<T>("smooth_graph f32", "smooth_graph f64");
    let r = meter.measure(name, || {
        smooth_graph(
            &g,
            &mut values,
            TaubinParams::paper(),
            10,
            &gopts,
            &mut scratch,
        )
    });
    if r.is_err() {
        fail(name);
    }
}

// ---------------------------------------------------------------------------------------------
// Multigrid on the small spring system

/// `u32` entries of the hierarchy's symbolic `work` buffer: `4 (N + E) + 64`
/// (`setup_work_len`, checked against it).
const AMG_WORK: usize = 4 * (SN + SE_USED) + 64;
/// Hierarchy `index` and `values` buffers: the exact sizes `setup_len` gives for the small
/// system (63 `u32`, 29 reals; checked, and printed, at run time) rounded up.
const AMG_INDEX: usize = 64;
const AMG_VALUES: usize = 32;
/// Coarse unknowns the solve scratch (`5 N + 3 × coarse` items) allows for (the hierarchy has
/// one).
const AMG_COARSE: usize = 1;

/// Largest `|a|` over all components.
fn max_abs<T: Real, const V: usize>(a: &[[T; V]]) -> T {
    a.iter()
        .flatten()
        .fold(T::ZERO, |m, &x| if x.abs() > m { x.abs() } else { m })
}

/// Largest componentwise `|a − b|` (a NaN difference counts as infinite).
fn max_diff<T: Real, const V: usize>(a: &[[T; V]], b: &[[T; V]]) -> T {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(T::ZERO, |m, (&x, &y)| {
            let d = (x - y).abs();
            if d.is_nan() {
                T::INFINITY
            } else if d > m {
                d
            } else {
                m
            }
        })
}

/// Agreement between two converged solutions relative to the data size, as in the on-target
/// `spring` tests: the residual tolerance (1e-10 / 1.2e-5) times a condition allowance.
fn agree_tol<T: Real>() -> T {
    if T::MANTISSA_DIGITS == 24 {
        T::from_f64(2e-3)
    } else {
        T::from_f64(1e-7)
    }
}

/// Checks a multigrid solve against the one-level CG on the same data: both converged, the
/// fixed nodes' bits kept, the two solutions within [`agree_tol`] of the data size.
fn check_against_cg<T: Real>(
    name: &str,
    fixed: &[u8],
    data: &[[T; 2]],
    amg: (&[[T; 2]], SolveReport<T>),
    cg: (&[[T; 2]], SolveReport<T>),
) {
    let ((x, r), (y, rc)) = (amg, cg);
    if !(r.converged && rc.converged) {
        fail(name);
    }
    for ((v, d), &f) in x.iter().zip(data).zip(fixed) {
        if f != 0
            && (v[0].to_bits_u64() != d[0].to_bits_u64()
                || v[1].to_bits_u64() != d[1].to_bits_u64())
        {
            fail(name);
        }
    }
    let diff = max_diff(x, y);
    let tol = agree_tol::<T>() * max_abs(data);
    defmt::println!(
        "{=str}: {=usize} iterations (one-level CG {=usize}), residual {=f64}, max |AMG - CG| {=f64} (tolerance {=f64})",
        name,
        r.iterations,
        rc.iterations,
        r.residual.to_f64(),
        diff.to_f64(),
        tol.to_f64()
    );
    if diff > tol {
        fail(name);
    }
}

/// The symbolic pass (`setup_len`) on `sys` with the default options, measured, in a frame of
/// its own with its own `work` buffer; fails unless the hierarchy will have at least two levels
/// and fits the buffers of [`multigrid`].
#[inline(never)]
fn amg_sizes<T: Real>(meter: &mut Meter, sys: &SpringSystem<'_, T>) -> AmgSizes {
    let opts = AmgOptions::<T>::default();
    let mut work = [0u32; AMG_WORK];
    if AmgHierarchy::setup_work_len(sys) > work.len() {
        fail("AMG: work buffer shorter than setup_work_len");
    }
    let name = tagged::<T>("AmgHierarchy::setup_len f32", "AmgHierarchy::setup_len f64");
    let sizes = match meter.measure(name, || AmgHierarchy::setup_len(sys, &opts, &mut work)) {
        Ok(s) => s,
        Err(e) => kernel_error(name, e),
    };
    defmt::println!(
        "AMG hierarchy of the 20-node system: {=usize} levels, {=usize} coarse unknowns, index {=usize} u32, values {=usize} reals, work {=usize} u32, the AmgHierarchy value {=usize} bytes",
        sizes.levels,
        sizes.coarse_unknowns,
        sizes.index,
        sizes.values,
        AmgHierarchy::setup_work_len(sys),
        core::mem::size_of::<AmgHierarchy<'_, T>>()
    );
    if sizes.levels < 2 {
        fail("AMG: the hierarchy has fewer than two levels");
    }
    if sizes.index > AMG_INDEX || sizes.values > AMG_VALUES || sizes.coarse_unknowns > AMG_COARSE {
        fail("AMG: the hierarchy does not fit its buffers");
    }
    sizes
}

/// `AmgHierarchy::setup` with the default options and a `work` buffer in this frame (transient:
/// gone when the hierarchy is returned). The hierarchy value (about 2 KB in f32, 3 KB in f64:
/// its level table and smoothing weights) is returned straight into the caller's frame.
#[inline(never)]
fn amg_build<'a, T: Real>(
    sys: &SpringSystem<'_, T>,
    index: &'a mut [u32],
    values: &'a mut [T],
) -> Result<AmgHierarchy<'a, T>, Error> {
    let mut work = [0u32; AMG_WORK];
    AmgHierarchy::setup(sys, &AmgOptions::default(), &mut work, index, values)
}

/// `solve_linear_amg` with `h`, measured, against the one-level CG (Jacobi) on the same data.
#[inline(never)]
fn amg_linear<T: Real>(
    meter: &mut Meter,
    sys: &SpringSystem<'_, T>,
    h: &AmgHierarchy<'_, T>,
    fixed: &[u8],
) {
    let data = small_values::<T, 2>();
    let opts = SolveOptions::default();
    let mut scratch = [[T::ZERO; 2]; 5 * SN + 3 * AMG_COARSE];
    let mut values = data;
    let len = solve_linear_amg_scratch_len(h);
    let name = tagged::<T>("solve_linear_amg f32", "solve_linear_amg f64");
    let r = meter.measure(name, || {
        sys.solve_linear_amg(
            h,
            &mut values,
            &opts,
            scratch.get_mut(..len).unwrap_or(&mut []),
        )
    });
    let r = r.unwrap_or_else(|e| kernel_error(name, e));
    let mut cg = data;
    let method = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let clen = solve_linear_scratch_len(&method, SN);
    let rc = below(|| {
        sys.solve_linear(
            &mut cg,
            method,
            &opts,
            scratch.get_mut(..clen).unwrap_or(&mut []),
        )
    })
    .unwrap_or_else(|e| kernel_error("solve_linear CG-Jacobi", e));
    check_against_cg(name, fixed, &data, (&values, r), (&cg, rc));
}

/// `solve_angle_amg` with `h` (ε = 0.01, as `solve_angle CG`), measured, against the
/// block-Jacobi CG (`AngleMethod::Cg`) on the same data.
#[inline(never)]
fn amg_angle<T: Real>(
    meter: &mut Meter,
    sys: &SpringSystem<'_, T>,
    h: &AmgHierarchy<'_, T>,
    m: &Small<T>,
) {
    let asys = match AngleSystem::new(*sys, &m.points, T::from_f64(0.01)) {
        Ok(a) => a,
        Err(e) => kernel_error("angle system", e),
    };
    let data = small_values::<T, 2>();
    let opts = SolveOptions::default();
    let mut scratch = [[T::ZERO; 2]; 5 * SN + 3 * AMG_COARSE];
    let mut values = data;
    let len = asys.angle_amg_scratch_len(h);
    let name = tagged::<T>("solve_angle_amg f32", "solve_angle_amg f64");
    let r = meter.measure(name, || {
        asys.solve_angle_amg(
            h,
            &mut values,
            &opts,
            scratch.get_mut(..len).unwrap_or(&mut []),
        )
    });
    let r = r.unwrap_or_else(|e| kernel_error(name, e));
    let mut cg = data;
    let clen = asys.angle_scratch_len(AngleMethod::Cg);
    let rc = below(|| {
        asys.solve_angle(
            &mut cg,
            AngleMethod::Cg,
            &opts,
            scratch.get_mut(..clen).unwrap_or(&mut []),
        )
    })
    .unwrap_or_else(|e| kernel_error("solve_angle CG", e));
    check_against_cg(name, &m.fixed, &data, (&values, r), (&cg, rc));
}

/// The multigrid entry points on the small spring system: one hierarchy (default options,
/// two levels), then `solve_linear_amg` and `solve_angle_amg` with it.
#[inline(never)]
fn multigrid<T: Real>(meter: &mut Meter) {
    let m = small::<T>();
    with_system(&m, |sys| multigrid_on(meter, sys, &m));
}

/// [`multigrid`] on the system. The symbolic pass, the setup and each solve run in non-inlined
/// functions of their own, so only the system, the hierarchy and its two buffers stay on the
/// stack throughout: the f64 setup needs most of the stack left beside the 960-node statics.
#[inline(never)]
fn multigrid_on<T: Real>(meter: &mut Meter, sys: &SpringSystem<'_, T>, m: &Small<T>) {
    let sizes = amg_sizes(meter, sys);
    let mut index = [0u32; AMG_INDEX];
    let mut hv = [T::ZERO; AMG_VALUES];
    let name = tagged::<T>(
        "AmgHierarchy::setup (with its work buffer) f32",
        "AmgHierarchy::setup (with its work buffer) f64",
    );
    // `amg_build` writes the hierarchy straight into `r`; through `meter.measure` it was copied
    // on the way out (this frame measured 6.6 KB instead of 3.6 KB in f64).
    let sp = meter.start();
    let r = amg_build(sys, &mut index, &mut hv);
    black_box(&r);
    meter.finish(name, sp);
    let h = match &r {
        Ok(h) => h,
        Err(e) => kernel_error(name, *e),
    };
    if h.levels() < 2 || h.levels() != sizes.levels {
        fail("AMG: the hierarchy has fewer than two levels");
    }
    amg_linear(meter, sys, h, &m.fixed);
    amg_angle(meter, sys, h, m);
}

/// Stack of every small entry point in precision `T`.
fn small_entry_points<T: Real>(meter: &mut Meter) {
    linear_cg::<T>(meter);
    linear_gs::<T>(meter);
    angle_cg::<T>(meter);
    spring_deformation::<T>(meter);
    multigrid::<T>(meter);
    graph_smoothing::<T>(meter);
}

#[entry]
fn main() -> ! {
    // SAFETY: the only reference to BIG, taken once before anything else runs.
    let big: &'static mut Big = unsafe { &mut *core::ptr::addr_of_mut!(BIG) };
    let mut meter = Meter {
        peak_depth: 0,
        overflow: false,
    };
    let statics = stack::bottom() - 0x2000_0000;
    defmt::println!(
        "footprint: RAM {=usize} bytes; statics (.data + .bss, incl. the 960-node buffers) {=usize} bytes; stack area {=usize} bytes",
        RAM_BYTES,
        statics,
        stack::top() - stack::bottom()
    );

    let x = meter.measure("quaternion ops f32", quat_ops::<f32>);
    let y = meter.measure("quaternion ops f64", quat_ops::<f64>);
    if !(x.is_finite() && y.is_finite()) {
        fail("quaternion ops");
    }

    small_entry_points::<f32>(&mut meter);
    small_entry_points::<f64>(&mut meter);

    // The 960-node deformation, IDW then TFI.
    build_big(big);
    let r = {
        let b = &mut *big;
        let motion = BoundaryMotion {
            nodes: &b.nodes,
            deformed: &b.deformed,
            elements: None,
            rotations: RotationSource::PerNode(&b.node_rotations),
            origin: None,
        };
        let len = deform_idw_scratch_len::<2>(N, NB).min(b.scratch.len());
        meter.measure("deform_idw (960 nodes) f32", || {
            deform_idw(
                &b.points,
                &motion,
                2.0,
                &mut b.translations,
                &mut b.rotations,
                b.scratch.get_mut(..len).unwrap_or(&mut []),
                &mut b.out,
            )
        })
    };
    if let Err(e) = r {
        kernel_error("deform_idw", e);
    }
    check_big(big, "deform_idw result");
    let block = match Block::new([NI, NJ, 1]) {
        Ok(b) => b,
        Err(e) => kernel_error("block", e),
    };
    let r = {
        let b = &mut *big;
        let motion = BoundaryMotion {
            nodes: &b.nodes,
            deformed: &b.deformed,
            elements: None,
            rotations: RotationSource::PerNode(&b.node_rotations),
            origin: None,
        };
        let len = deform_tfi_scratch_len::<2>(&block, NB).min(b.scratch.len());
        meter.measure("deform_tfi (960 nodes) f32", || {
            deform_tfi(
                &block,
                Directions::from_flags([true, true, false]),
                &b.points,
                &motion,
                &mut b.translations,
                &mut b.rotations,
                b.scratch.get_mut(..len).unwrap_or(&mut []),
                &mut b.out,
            )
        })
    };
    if let Err(e) = r {
        kernel_error("deform_tfi", e);
    }
    check_big(big, "deform_tfi result");
    defmt::println!("footprint: 960-node deformations (deform_idw, deform_tfi) ok: boundary bit-exact, no folded grid line");

    // Taubin on the 960-node block: the scalar filter on x, then arclength smoothing of
    // the deformed grid along i.
    let r = {
        let b = &mut *big;
        let (field, scratch) = b.scratch.split_at_mut(N);
        for (f, p) in field.iter_mut().zip(&b.out) {
            *f = p[0];
        }
        let opts = StructuredOptions {
            fixed: None,
            mirror: Directions::NONE,
        };
        meter.measure("smooth_structured (960 points) f32", || {
            smooth_structured(&block, field, TaubinParams::paper(), 10, &opts, scratch)
        })
    };
    if r.is_err() {
        fail("smooth_structured");
    }
    let r = {
        let b = &mut *big;
        let len =
            smooth_arclength_scratch_len::<2>(&block, Direction::I, None).min(b.scratch.len());
        let opts = SmoothOptions::new(Direction::I);
        meter.measure("smooth_arclength (960 points) f32", || {
            smooth_arclength(
                &block,
                &mut b.out,
                &opts,
                b.scratch.get_mut(..len).unwrap_or(&mut []),
            )
        })
    };
    if r.is_err() {
        fail("smooth_arclength");
    }

    let total = statics + meter.peak_depth;
    defmt::println!(
        "footprint: RAM used = statics {=usize} + peak stack {=usize} = {=usize} of {=usize} bytes ({=usize} free)",
        statics,
        meter.peak_depth,
        total,
        RAM_BYTES,
        RAM_BYTES.saturating_sub(total)
    );
    if meter.overflow || total > RAM_BYTES {
        fail("the run does not fit in 64 KiB");
    }
    defmt::println!("footprint: ok");
    semihosting::process::exit(0)
}
