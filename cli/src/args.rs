//! The command line, as clap derive structures (doc comments are the `--help` text).

use std::path::PathBuf;

use clap::{ArgGroup, Args, Parser, Subcommand, ValueEnum};

mod rbf;
mod sensitivity;
pub use rbf::{check_rbf_args, RbfArgs, RbfKernelArg};
pub use sensitivity::{
    AdjointArgs, GridMotionArgs, SensitivityMethod, SensitivitySetup, TangentArgs,
    DEFAULT_IDW_EXPONENT, DEFAULT_MAX_ITER, DEFAULT_TOL,
};

/// Deform, smooth and check real mesh files (SU2, Plot3D, VTK) with deform-kernel.
///
/// Exit status: 0 success, 1 bad input or failed run (nothing written), 2 bad command line,
/// 3 feature not available yet in this build, 4 the result would have cells that the input
/// did not have inverted or folded (nothing written; `--allow-folds` writes it), 5 a solve did
/// not converge (nothing written; `--allow-unconverged` writes it), 128 + N killed by signal N.
#[derive(Debug, Parser)]
#[command(name = "deform", version)]
pub struct Cli {
    /// Print a machine-readable JSON report on stdout (and no progress bars).
    #[arg(long, global = true)]
    pub json: bool,
    /// Read input meshes as this format instead of detecting it from their content (SU2 by
    /// its keywords, VTK XML by its header, anything else as Plot3D; the extension does not
    /// matter).
    #[arg(long, global = true, value_enum, value_name = "FORMAT")]
    pub format: Option<InputFormat>,
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// The `deform` commands.
// One value per run, parsed once: the size difference between variants costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run the papers' experiments on generated NACA 2412 meshes and write pictures and a report.
    Demo(DemoArgs),
    /// Generate meshes.
    #[command(subcommand)]
    Mesh(MeshCommand),
    /// Move boundary markers of an SU2 mesh and deform the volume mesh to follow.
    ///
    /// Failure policy (the same as `smooth`): a result with cells that the input did not have
    /// inverted or folded is not written (exit 4) unless --allow-folds, and a solve that stops
    /// before converging is an error (exit 5) unless --allow-unconverged; with the flag the
    /// output is written and the count or residual is reported (and warned about on stderr).
    Move(MoveArgs),
    /// Do SU2_DEF's job from its own configuration file: read MESH_FILENAME, apply the design
    /// variables (DV_KIND, DV_MARKER, DV_PARAM, DV_VALUE) to the surface, deform the volume and
    /// write MESH_OUT_FILENAME.
    ///
    /// File names are relative to the current directory, as for SU2_DEF. Options that mesh
    /// deformation does not use are listed once on stderr (and in the JSON report) as ignored;
    /// an option it cannot honour is an error naming it. The failure policy is `move`'s.
    Su2(Su2Args),
    /// Pull a volume sensitivity dJ/dx (SU2_CFD_AD's) back through the mesh deformation to the
    /// boundary nodes, as SU2_DOT does: the adjoint of the deformation (springs, angle springs,
    /// quaternion with spring or IDW propagation, IDW, RBF, elasticity; the nonlinear ones
    /// linearised about --deformed); with --config, on to dJ/dα of the config's design
    /// variables (SU2_DOT's of_grad.dat). On a Plot3D grid: the TFI of `deform move --wall`
    /// (--method tfi|tfi-displacement, about the move's --rotate/--translate), dJ/dx at the
    /// wall faces' nodes.
    Adjoint(AdjointArgs),
    /// The first-order motion of every node for one boundary perturbation (the tangent of the
    /// deformation, the nonlinear ones linearised about --deformed; on a Plot3D grid the TFI
    /// of `deform move --wall` about its --rotate/--translate, the wall faces' nodes perturbed).
    Tangent(TangentArgs),
    /// Smooth a Plot3D grid along one grid direction (Alter's arclength Taubin smoothing).
    ///
    /// Points slide along their own grid lines to the filtered arclength; the first and last
    /// point of every line never move (bit for bit), and neither does any point that
    /// coincides with another grid point (O-grid seams, block interfaces), so seams and
    /// interfaces stay closed. Without --normalized the physical arclength is filtered (this
    /// smooths the grid: points are redistributed between the fixed ends); with --normalized
    /// the arclength divided by each line's length is filtered (this reduces stretching).
    /// --free-end kmax lets the last points of the k-lines slide too (Alter's rough outer
    /// boundary of a solution-adapted grid), in every block or per block (--free-end 2:kmax).
    /// If a line folds (arclength stops increasing) or a cell flips (a corner Jacobian that
    /// was positive becomes ≤ 0) the run stops with an error naming the block, the line or
    /// cell and the iteration, and nothing is written (exit 4, the policy `move` shares;
    /// --allow-folds writes flipped cells anyway and reports them). Reports the largest stretching ratio and Alter's stretching
    /// measure ∇²S before and after.
    Smooth(SmoothArgs),
    /// Report mesh quality (signed measures, inverted and folded cells, area ratios).
    Quality(QualityArgs),
    /// Convert between formats: SU2 → SU2/VTU, Plot3D → Plot3D (any layout)/VTS.
    Convert(ConvertArgs),
}

/// `deform demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Directory for pictures, VTK files and the report.
    #[arg(long, default_value = "deform-demo")]
    pub out: PathBuf,
    /// A fast check: 384-node meshes, one angle (20°), smaller grids, and no angle-direct
    /// runs (Gauss–Seidel on the angle springs needs thousands of sweeps).
    #[arg(long)]
    pub quick: bool,
}

/// `deform mesh …`.
#[derive(Debug, Subcommand)]
pub enum MeshCommand {
    /// A NACA 4-digit airfoil mesh.
    Naca(NacaArgs),
    /// A structured block (optionally jittered, as a smoothing test case).
    Block(BlockArgs),
}

/// Kinds of NACA mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NacaKind {
    /// Triangles everywhere (Euler).
    Inviscid,
    /// Quads near the wall, triangles outside (Navier–Stokes).
    Viscous,
    /// A structured O-grid of quads.
    Ogrid,
}

/// `deform mesh naca`. Size options default to the kind's preset (inviscid: 160 × 56,
/// first layer 2e-3; viscous and O-grid: 160 × 64, first layer 1e-5, 24 quad layers).
#[derive(Debug, Args)]
pub struct NacaArgs {
    /// The 4-digit NACA code.
    #[arg(long, default_value = "2412")]
    pub code: String,
    /// The kind of mesh.
    #[arg(long, value_enum)]
    pub kind: NacaKind,
    /// Points around the airfoil (even, at least 8).
    #[arg(long)]
    pub surface_points: Option<usize>,
    /// Points from the wall to the far field (at least 3).
    #[arg(long)]
    pub radial_points: Option<usize>,
    /// Far-field radius in chords.
    #[arg(long)]
    pub farfield: Option<f64>,
    /// First cell height at the wall, in chords.
    #[arg(long)]
    pub first_layer: Option<f64>,
    /// Quad layers next to the wall (viscous kind).
    #[arg(long)]
    pub boundary_layers: Option<usize>,
    /// Output mesh: .su2 (or .vtu to look at it).
    #[arg(long)]
    pub out: PathBuf,
}

/// `deform mesh block`.
#[derive(Debug, Args)]
pub struct BlockArgs {
    /// Points per direction: ni,nj (2D) or ni,nj,nk (3D).
    #[arg(long, value_parser = parse_dims)]
    pub dims: Dims,
    /// Random jitter of interior points, as a fraction of the local spacing (below 0.4).
    #[arg(long, default_value_t = 0.0)]
    pub noise: f64,
    /// Seed of the jitter.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output grid: Plot3D (.x .xyz .p3d .g .grd .xy: binary f64 with Fortran records;
    /// .xyz and .p3d as ASCII), .vts, or .su2.
    #[arg(long)]
    pub out: PathBuf,
}

/// Block dimensions from the command line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Dims(pub Vec<usize>);

fn parse_dims(s: &str) -> Result<Dims, String> {
    let v: Result<Vec<usize>, _> = s.split(',').map(|t| t.trim().parse::<usize>()).collect();
    match v {
        Ok(v) if (v.len() == 2 || v.len() == 3) && v.iter().all(|&d| d >= 2) => Ok(Dims(v)),
        _ => Err(format!(
            "expected ni,nj or ni,nj,nk (each at least 2), found {s:?}"
        )),
    }
}

/// Deformation methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Samareh's quaternion method, rotations and translations propagated by linear springs.
    Quaternion,
    /// Batina's linear springs.
    Spring,
    /// Yang & Özgen angle-inclusion springs, node-wise direct solve.
    AngleDirect,
    /// Yang & Özgen angle-inclusion springs, conjugate gradients.
    AngleCg,
    /// Samareh's quaternion method, propagated by inverse-distance weighting.
    Idw,
    /// Samareh's quaternion transfinite interpolation (Plot3D grids, with --wall).
    Tfi,
    /// Plain displacement transfinite interpolation (Plot3D grids, with --wall).
    TfiDisplacement,
    /// Radial basis functions (SU2's and pyGeM's RBF): Wendland C2 or thin-plate splines,
    /// greedy centres, the wall kept exact (--rbf-* options).
    Rbf,
    /// Finite-element linear elasticity (SU2_DEF's method): the mesh is an elastic solid with
    /// Young's modulus per cell from --stiffness (default inverse-volume) and Poisson ratio
    /// --poisson; --steps N applies the boundary displacement in N equal increments,
    /// re-assembling the stiffness on the updated mesh (SU2's DEFORM_NONLINEAR_ITER).
    Elasticity,
}

/// A face of a structured block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FaceArg {
    /// i = 1.
    Imin,
    /// i = ni.
    Imax,
    /// j = 1.
    Jmin,
    /// j = nj.
    Jmax,
    /// k = 1.
    Kmin,
    /// k = nk.
    Kmax,
}

/// Which blocks `--wall` moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WallBlocks {
    /// A bare face: the only block of a single-block grid (refused on several blocks).
    Unnamed,
    /// Block N (1-based).
    One(usize),
    /// `all:FACE`: every block.
    All,
}

/// `--wall [BLOCK:]FACE`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WallArg {
    /// Which blocks.
    pub blocks: WallBlocks,
    /// Which face of them.
    pub face: FaceArg,
}

fn parse_wall(s: &str) -> Result<WallArg, String> {
    let (block, face) = match s.split_once(':') {
        Some((b, f)) => (Some(b.trim()), f.trim()),
        None => (None, s.trim()),
    };
    let face = FaceArg::from_str(face, true).map_err(|_| {
        format!("{face:?} is not a face (imin, imax, jmin, jmax, kmin, kmax), in {s:?}")
    })?;
    let blocks = match block {
        None => WallBlocks::Unnamed,
        Some(b) if b.eq_ignore_ascii_case("all") => WallBlocks::All,
        Some(b) => match b.parse::<usize>() {
            Ok(n) if n >= 1 => WallBlocks::One(n),
            _ => return Err(format!("{b:?} is not a block number (1, 2, …) or all")),
        },
    };
    Ok(WallArg { blocks, face })
}

/// Spring stiffness (`--stiffness`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum StiffnessArg {
    /// Batina's 1/L (the papers' choice).
    Batina,
    /// 1/L times d̄/d, d the distance to the moved markers (SU2's WALL_DISTANCE): cells near
    /// the moving wall move almost rigidly with it.
    WallDistance,
    /// 1/L times V̄/V, V the node's dual volume (SU2's INVERSE_VOLUME): small cells are stiffer.
    /// --method elasticity: Young's modulus E = 1/V per cell.
    InverseVolume,
    /// --method elasticity only: the same Young's modulus in every cell (SU2's
    /// CONSTANT_STIFFNESS).
    Constant,
}

/// Linear solvers for the spring methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Solver {
    /// Conjugate gradients preconditioned by smoothed-aggregation algebraic multigrid.
    Amg,
    /// Jacobi-preconditioned conjugate gradients.
    #[value(alias = "cg-jacobi")]
    Cg,
    /// SSOR-preconditioned conjugate gradients (ω = 1.5).
    CgSsor,
    /// Gauss–Seidel.
    Gs,
    /// Jacobi.
    Jacobi,
}

/// `deform move`.
#[derive(Clone, Debug, Args)]
#[command(group(ArgGroup::new("motion").required(true).args(["rotate", "translate", "displacements", "surface_positions", "motions"])))]
pub struct MoveArgs {
    /// The SU2 mesh, or a Plot3D grid (with --method tfi|tfi-displacement and --wall).
    pub mesh: PathBuf,
    /// A marker to move (repeat for several; SU2 meshes); markers not named stay fixed.
    #[arg(long = "marker")]
    pub markers: Vec<String>,
    /// A symmetry marker whose nodes slide on its plane (a line in 2D) instead of staying
    /// fixed (repeat for several; SU2 meshes). The plane is fitted to the marker's nodes and
    /// must be flat (residual at most 1e-6 of the marker's size); nodes on two sliding planes
    /// slide along the line where they meet; nodes also on a moved or fixed marker follow that
    /// marker.
    #[arg(long = "slide", value_name = "MARKER")]
    pub slide: Vec<String>,
    /// Plot3D grids: the block face that moves (imin, imax, jmin, jmax, kmin, kmax); the
    /// opposite face stays and the points in between follow by transfinite interpolation along
    /// that direction. A grid of several blocks needs the block, 1-based: `2:jmin` moves block
    /// 2's jmin face and leaves the other blocks as they are (`all:jmin`: that face of every
    /// block); a bare face is refused there rather than guessed.
    #[arg(long, value_name = "[BLOCK:]FACE", value_parser = parse_wall)]
    pub wall: Option<WallArg>,
    /// Rotate the markers by DEG degrees, counter-clockwise about the axis (right-hand rule).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub rotate: Option<f64>,
    /// Rotation axis x,y,z (default z).
    #[arg(long, value_name = "X,Y,Z", requires = "rotate", value_parser = parse_vec3)]
    pub axis: Option<Coords>,
    /// Rotation centre x,y or x,y,z (default: centroid of the moved markers' nodes).
    #[arg(long, value_name = "X,Y[,Z]", requires = "rotate", value_parser = parse_vec23, allow_hyphen_values = true)]
    pub center: Option<Coords>,
    /// Translate the markers by dx,dy (2D) or dx,dy,dz (3D).
    #[arg(long, value_name = "DX,DY[,DZ]", value_parser = parse_vec23, allow_hyphen_values = true)]
    pub translate: Option<Coords>,
    /// Prescribed displacements: lines `node dx dy [dz]` (0-based node, `%` or `#` comments);
    /// marker nodes not listed do not move.
    #[arg(long, value_name = "FILE")]
    pub displacements: Option<PathBuf>,
    /// New positions of marker nodes, as SU2_DEF reads them (DV_KIND= SURFACE_FILE): lines
    /// `GlobalIndex x y [z]` (0-based node, absolute coordinates); marker nodes not listed do
    /// not move.
    #[arg(long, value_name = "FILE")]
    pub surface_positions: Option<PathBuf>,
    /// A different rigid motion per marker: lines `MARKER rotate DEG [center X,Y[,Z]] [axis
    /// X,Y,Z]` or `MARKER translate DX,DY[,DZ]` (`%`/`#` comments). The markers named there
    /// move (no --marker); a node on two markers must get the same motion from both.
    #[arg(long, value_name = "FILE", conflicts_with = "markers")]
    pub motions: Option<PathBuf>,
    /// Deformation method. Default: the most robust one for a rigid motion, `quaternion` on
    /// SU2 meshes (Samareh's quaternion method: a rotating wall keeps its boundary layer;
    /// linear springs fold cells at a few degrees) and `tfi` (quaternion TFI) on Plot3D grids.
    #[arg(long, value_enum)]
    pub method: Option<Method>,
    /// Linear solver (quaternion and spring). angle-direct: over-relaxed node-wise sweeps
    /// (SOR, omega from the mesh size, about 1.97 at 10k nodes) unless gs (plain
    /// Gauss–Seidel) or jacobi (Jacobi order) is asked for. angle-cg: amg preconditions CG
    /// with the linear springs' multigrid (with --slide too), any other choice with the node
    /// blocks.
    #[arg(long, value_enum, default_value = "amg")]
    pub solver: Solver,
    /// Multigrid strength threshold θ in [0, 1) for `--solver amg` with the spring,
    /// quaternion and angle-cg methods (elasticity's multigrid keeps every connection).
    /// A spring is strong when it is at least θ times the geometric mean of the stiffest
    /// springs at its two ends. Default 0.25: on a stretched boundary layer the multigrid
    /// coarsens along the layer (234k-node NACA mesh: 52 → 30 iterations for the springs,
    /// quaternion adjoint about 1.2× its deformation), on isotropic meshes nothing changes;
    /// 0 makes every spring strong (pyamg's default; docs/amg.md).
    #[arg(long, value_name = "THETA")]
    pub amg_strength: Option<f64>,
    /// Spring stiffness of the spring, angle-spring and quaternion methods (IDW and TFI have
    /// no springs; default batina). On the viscous NACA 2412 pitched 10°, linear springs
    /// invert 69 cells with batina, 34 with wall-distance and 0 with inverse-volume.
    /// --method elasticity: Young's modulus per cell, inverse-volume (default), wall-distance
    /// (E = 1/d, d the cell's mean distance to the moved markers) or constant.
    #[arg(long, value_enum)]
    pub stiffness: Option<StiffnessArg>,
    /// --method elasticity: Poisson ratio, in (-1, 0.5) (above 0.5: SU2's DEFORM_COEFF
    /// convention, a near-zero bulk modulus).
    #[arg(long, default_value_t = 0.3, allow_hyphen_values = true)]
    pub poisson: f64,
    /// --method elasticity: the nodes within this distance of the moved markers move rigidly
    /// with them (so the first grid lines keep their angle to the wall); the rest is solved.
    /// Rigid motions (--rotate, --translate) only. With --poisson 0.45 the best method on the
    /// viscous NACA 2412 pitched 50° (docs/methods.md, "Elasticity with a rigid wall layer").
    #[arg(long, value_name = "DIST")]
    pub rigid_layer: Option<f64>,
    /// Move in N increments: each step moves the markers by 1/N of the motion starting from
    /// the previous step's mesh, so stiffness and rotations follow the deforming mesh (large
    /// rotations); the last step ends exactly on the prescribed motion.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub steps: u32,
    /// Convergence tolerance on the relative residual.
    #[arg(long, default_value_t = 1e-10)]
    pub tol: f64,
    /// Iteration limit.
    #[arg(long, default_value_t = 10_000)]
    pub max_iter: usize,
    /// Inverse-distance exponent for --method idw and the quaternion IDW propagation. 2 is the
    /// robust default: on the NACA meshes 3 and 5 fold cells at 50° (docs/deformation-naca.md).
    #[arg(long, default_value_t = 2.0)]
    pub idw_exponent: f64,
    /// --method idw only: the fast tree-based propagation (far-field clusters of boundary
    /// nodes, opening parameter THETA in [0, 1), e.g. 0.5) instead of the exact O(N·B) sums;
    /// for large 3D meshes (10^6 × 10^5 nodes: seconds instead of minutes). The report gives
    /// the largest per-point error bound, relative to the spread of the boundary motion.
    #[arg(long, value_name = "THETA")]
    pub idw_theta: Option<f64>,
    /// Largest accepted per-point error bound of the fast IDW (clusters are opened until it
    /// holds; needs --idw-theta).
    #[arg(
        long,
        value_name = "ETA",
        default_value_t = 0.1,
        requires = "idw_theta"
    )]
    pub idw_tolerance: f64,
    /// Quaternion and IDW methods: fade the propagated motion smoothly to none at this
    /// distance from the moved markers (mesh units), so far-away nodes stay put (by default a
    /// small interpolated rotation turns far nodes about the rotation origin).
    #[arg(long, value_name = "DISTANCE")]
    pub reach: Option<f64>,
    /// Write the result even if it has cells that the input did not have inverted or
    /// folded, and report them (default: refuse with exit status 4, write nothing).
    #[arg(long)]
    pub allow_folds: bool,
    /// Write the result even if a solve stopped before reaching --tol within --max-iter,
    /// and report it (default: refuse with exit status 5, write nothing).
    #[arg(long)]
    pub allow_unconverged: bool,
    /// Node numbering for the solve (SU2 meshes): the output is always in the input's
    /// numbering. auto: reverse Cuthill–McKee when the mesh has at least 20 000 nodes and its
    /// numbering scatters neighbours (as mesh generators write them), else as given; rcm or
    /// hilbert: always; off: never (a mesh a solver already ordered).
    #[arg(long, value_enum, default_value = "auto")]
    pub renumber: crate::renumber::Renumber,
    /// Output SU2 mesh.
    #[arg(long)]
    pub out: PathBuf,
    /// Also write a VTK .vtu file with displacement and cell-quality fields.
    #[arg(long)]
    pub vtk: Option<PathBuf>,
    /// A displacement per moved node computed by the caller (`deform su2`'s design
    /// variables); not a command-line option.
    #[arg(skip)]
    pub design_field: Option<Vec<(u32, [f64; 3])>>,
    /// --method rbf options.
    #[command(flatten)]
    pub rbf: RbfArgs,
    /// Also draw the deformed mesh (.svg or .png) around the moved markers, folded or inverted
    /// cells in red. A 3D mesh is drawn as its section by the plane z = const through the
    /// middle of the moved markers.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Under mpirun (a build with the `mpi` feature): each process reads, holds, solves and
    /// writes only its part of the mesh (--method spring or quaternion, --solver cg, a rigid
    /// motion of markers; other options are refused); the output is the serial run's, byte
    /// for byte.
    #[arg(long)]
    pub distributed: bool,
}

impl MoveArgs {
    /// `--method`, or the default for an SU2 mesh: the quaternion method (`deform move` on a
    /// Plot3D grid fills in `tfi` before anything reads it).
    pub fn method(&self) -> Method {
        self.method.unwrap_or(Method::Quaternion)
    }

    /// `--stiffness`, or the method's default: inverse-volume for elasticity, batina else.
    pub fn stiffness(&self) -> StiffnessArg {
        match (self.stiffness, self.method()) {
            (Some(s), _) => s,
            (None, Method::Elasticity) => StiffnessArg::InverseVolume,
            (None, _) => StiffnessArg::Batina,
        }
    }
}

/// Grid directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Direction {
    /// Along i.
    I,
    /// Along j.
    J,
    /// Along k (3D grids only).
    K,
}

/// Plot3D layout overrides (detection is automatic; use these when a file is ambiguous).
#[derive(Debug, Args, Default, Clone)]
pub struct LayoutArgs {
    /// Dimension of the Plot3D grid.
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub dim: Option<u8>,
    /// Real width of a binary Plot3D file.
    #[arg(long, value_enum)]
    pub precision: Option<PrecisionArg>,
    /// Byte order of a binary Plot3D file.
    #[arg(long, value_enum)]
    pub endian: Option<EndianArg>,
    /// Fortran record markers: yes or no.
    #[arg(long, value_enum)]
    pub records: Option<YesNo>,
    /// iblank present: yes or no.
    #[arg(long, value_enum)]
    pub iblank: Option<YesNo>,
    /// Number-of-blocks header present: yes or no.
    #[arg(long, value_enum)]
    pub multi_block: Option<YesNo>,
    /// Text (ascii) or binary.
    #[arg(long, value_enum)]
    pub encoding: Option<EncodingArg>,
}

/// Real widths.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    /// 32-bit.
    F32,
    /// 64-bit.
    F64,
}

/// Byte orders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EndianArg {
    /// Little endian.
    Little,
    /// Big endian.
    Big,
}

/// Yes or no.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum YesNo {
    /// Yes.
    Yes,
    /// No.
    No,
}

/// Text or binary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EncodingArg {
    /// Text.
    Ascii,
    /// Binary.
    Binary,
}

/// `deform su2`.
#[derive(Clone, Debug, Args)]
pub struct Su2Args {
    /// The SU2 configuration file (as given to SU2_DEF).
    pub config: PathBuf,
    /// Deform the volume by this method instead of SU2's finite-element elasticity.
    #[arg(long, value_enum)]
    pub method: Option<Method>,
    /// Write the result even if cells fold or invert (see `deform move`).
    #[arg(long)]
    pub allow_folds: bool,
    /// Write the result even if the solver does not converge (see `deform move`).
    #[arg(long)]
    pub allow_unconverged: bool,
}

/// `deform smooth`.
#[derive(Debug, Args)]
pub struct SmoothArgs {
    /// The Plot3D grid.
    pub grid: PathBuf,
    /// Grid direction to smooth along.
    #[arg(long, value_enum)]
    pub direction: Direction,
    /// Filter the normalised arclength S/S_line (reduces stretching) instead of the physical
    /// arclength S (smooths the grid). Line ends stay fixed unless --free-end frees them.
    #[arg(long)]
    pub normalized: bool,
    /// Let the last points of the lines slide along their lines (past the end along the last
    /// segment): the face at the end of the smoothing direction (imax, jmax or kmax), in
    /// every block or in block B (1-based) with B:FACE; repeatable. Needs the physical
    /// arclength; a face point that coincides with another grid point (a seam, an interface)
    /// is refused.
    #[arg(long, value_name = "[B:]FACE")]
    pub free_end: Vec<String>,
    /// Write the result even if cells flip, and report them (default: refuse with exit status
    /// 4, write nothing).
    #[arg(long)]
    pub allow_folds: bool,
    /// Number of λ|μ iterations.
    #[arg(long)]
    pub iterations: usize,
    /// Taubin λ (positive).
    #[arg(long, default_value_t = 0.33)]
    pub lambda: f64,
    /// Taubin μ (≤ 0; |μ| slightly above λ gives a low-pass filter; 0 gives plain Laplacian
    /// smoothing).
    #[arg(long, default_value_t = -0.334, allow_hyphen_values = true)]
    pub mu: f64,
    /// Alter's coarse-grid pass after the fine iterations: keep every M-th point in the
    /// directions across the lines, run half as many iterations there, prolongate.
    #[arg(long, value_name = "M")]
    pub coarse: Option<usize>,
    /// Output Plot3D grid (same layout as the input).
    #[arg(long)]
    pub out: PathBuf,
    /// Input layout overrides.
    #[command(flatten)]
    pub layout: LayoutArgs,
}

/// `deform quality`.
#[derive(Debug, Args)]
pub struct QualityArgs {
    /// The mesh (SU2) or grid (Plot3D).
    pub file: PathBuf,
    /// The undeformed mesh, for inverted cells, area ratios and wall-angle changes.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Wall marker(s) for the first grid-line angle change (SU2, with --reference).
    #[arg(long = "wall", value_name = "MARKER")]
    pub walls: Vec<String>,
    /// Also write the mesh with per-cell quality fields: .vtu for SU2, .vts for Plot3D (one
    /// file per block, OUT_bN.vts, when there are several).
    #[arg(long)]
    pub vtk: Option<PathBuf>,
    /// Input layout overrides (Plot3D).
    #[command(flatten)]
    pub layout: LayoutArgs,
}

/// `deform convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// Input: .su2 (one or several zones), a Plot3D grid (.x, .xyz, .p3d, .g, .grd, .xy, or any
    /// name), or CGNS (builds with the cgns feature; unstructured reads as SU2, structured as
    /// Plot3D).
    pub input: PathBuf,
    /// Output: .su2, .vtu or .cgns from SU2; Plot3D, .vts or .cgns from Plot3D (one .vts per
    /// block, named OUT_bN.vts, when there are several blocks).
    pub output: PathBuf,
    /// Input layout overrides (Plot3D).
    #[command(flatten)]
    pub layout: LayoutArgs,
    /// Output Plot3D encoding (default: the input's).
    #[arg(long, value_enum)]
    pub out_encoding: Option<EncodingArg>,
    /// Output Plot3D real width (default: the input's, f64 for ASCII input).
    #[arg(long, value_enum)]
    pub out_precision: Option<PrecisionArg>,
    /// Output Plot3D byte order (default: the input's, little for ASCII input).
    #[arg(long, value_enum)]
    pub out_endian: Option<EndianArg>,
    /// Output Fortran record markers (default: the input's, yes for ASCII input).
    #[arg(long, value_enum)]
    pub out_records: Option<YesNo>,
    /// Write VTK data arrays as ASCII text instead of base64 binary.
    #[arg(long)]
    pub vtk_ascii: bool,
    /// SU2 input: rewrite the valid cells listed clockwise (2D) or mirrored (3D) in the
    /// SU2/VTK convention (counter-clockwise, right-handed; SU2 does the same when it reads
    /// them). Folded cells are left as they are.
    #[arg(long)]
    pub reorient: bool,
}

/// A comma-separated list of 2 or 3 finite numbers from the command line.
#[derive(Clone, Debug, PartialEq)]
pub struct Coords(pub Vec<f64>);

fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .map(|t| {
            let t = t.trim();
            match t.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(format!("{t:?} is not a finite number")),
            }
        })
        .collect()
}

fn parse_vec3(s: &str) -> Result<Coords, String> {
    let v = parse_list(s)?;
    if v.len() != 3 {
        return Err(format!(
            "expected 3 comma-separated numbers x,y,z, found {}",
            v.len()
        ));
    }
    Ok(Coords(v))
}

fn parse_vec23(s: &str) -> Result<Coords, String> {
    let v = parse_list(s)?;
    if v.len() != 2 && v.len() != 3 {
        return Err(format!(
            "expected 2 or 3 comma-separated numbers, found {}",
            v.len()
        ));
    }
    Ok(Coords(v))
}

/// Input formats for `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum InputFormat {
    /// SU2 native ASCII.
    Su2,
    /// Plot3D whole grid (any layout; see the layout options).
    Plot3d,
    /// VTK XML (.vtu/.vts): written by the tool, not read.
    Vtk,
    /// CGNS (HDF5 or ADF; builds with the cgns feature): unstructured as SU2, structured as Plot3D.
    Cgns,
}
