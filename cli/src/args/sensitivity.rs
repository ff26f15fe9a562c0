//! The arguments of `deform adjoint` and `deform tangent`.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

/// The linear deformation whose derivative the sensitivity commands take.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SensitivityMethod {
    /// Batina's linear springs (stiffness 1/length) on the mesh's edge graph, multigrid CG:
    /// `deform move --method spring --stiffness batina`'s solve.
    Spring,
    /// Inverse-distance weighting of the boundary displacements (`--idw-exponent`), rotations
    /// left out. Not `deform move --method idw`, whose quaternion rotations make it nonlinear
    /// (that one is `--method idw`).
    IdwDisplacements,
    /// Samareh's quaternion method with inverse-distance propagation (`deform move --method
    /// idw`, `--idw-exponent`; the fast tree-based form with `--idw-theta`/`--idw-tolerance`),
    /// rotations from the boundary shape, default origin. Nonlinear: linearised about the
    /// boundary of `--deformed` (the fast form with the forward's cluster choices held).
    Idw,
    /// Samareh's quaternion method with linear-spring propagation (`deform move --method
    /// quaternion`: Batina stiffness, multigrid CG), rotations from the boundary shape,
    /// default origin. Nonlinear: linearised about the boundary of `--deformed`.
    Quaternion,
    /// The angle-inclusion springs (Yang & Özgen; `deform move --method angle-cg`: Batina
    /// stiffness, face diagonals, ε = 0.01, multigrid CG).
    Angle,
    /// Radial basis functions (`deform move --method rbf` with the --rbf-* options), every
    /// marker's nodes as the boundary. Linear with every boundary node a centre; with greedy
    /// centres linearised about the boundary motion of `--deformed`, its centres kept.
    Rbf,
    /// Finite-element linear elasticity (`deform move --method elasticity` with the same
    /// --stiffness, --poisson and --steps; multigrid-preconditioned CG). One step is linear;
    /// with `--steps N` the boundary displacement of `--deformed` is applied in N equal
    /// increments re-assembled on the moved mesh, and that map is linearised.
    Elasticity,
    /// Plot3D grids: Samareh's quaternion TFI of `deform move --method tfi` (the default
    /// there), the rotations of the wall taken from its shape (for `deform move`'s rigid
    /// motions, the motion's own rotation), linearised about the motion of --rotate/--translate.
    Tfi,
    /// Plot3D grids: the displacement TFI of `deform move --method tfi-displacement` (linear).
    TfiDisplacement,
}

/// The wall and its rigid motion on a Plot3D grid (`deform move`'s options of the same names):
/// the linearisation point of `--method tfi`.
#[derive(Clone, Debug, Args)]
pub struct GridMotionArgs {
    /// Plot3D grids: the block face `deform move --wall` moved (`[BLOCK:]FACE`, `all:FACE`);
    /// its nodes are the ones perturbed (tangent) and written (adjoint); the opposite face stays.
    #[arg(long, value_name = "[BLOCK:]FACE", value_parser = super::parse_wall)]
    pub wall: Option<super::WallArg>,
    /// Plot3D grids: the `deform move --rotate DEG` of the linearisation point.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub rotate: Option<f64>,
    /// Plot3D grids: `deform move --axis` (default z).
    #[arg(long, value_name = "X,Y,Z", requires = "rotate", value_parser = super::parse_vec3)]
    pub axis: Option<super::Coords>,
    /// Plot3D grids: `deform move --center` (default: the centroid of the block's wall face);
    /// also the quaternion TFI's origin.
    #[arg(long, value_name = "X,Y[,Z]", requires = "rotate", value_parser = super::parse_vec23, allow_hyphen_values = true)]
    pub center: Option<super::Coords>,
    /// Plot3D grids: the `deform move --translate DX,DY[,DZ]` of the linearisation point.
    #[arg(long, value_name = "DX,DY[,DZ]", value_parser = super::parse_vec23, allow_hyphen_values = true)]
    pub translate: Option<super::Coords>,
}

impl GridMotionArgs {
    /// Whether any of these options was given (they belong to Plot3D grids).
    pub fn any(&self) -> bool {
        self.wall.is_some()
            || self.rotate.is_some()
            || self.axis.is_some()
            || self.center.is_some()
            || self.translate.is_some()
    }
}

/// `--idw-exponent`'s default (a Plot3D run, which has no IDW, refuses any other value).
pub const DEFAULT_IDW_EXPONENT: f64 = 2.0;
/// `--tol`'s default (a Plot3D run, which has no solve, refuses any other value).
pub const DEFAULT_TOL: f64 = 1e-12;
/// `--max-iter`'s default (a Plot3D run refuses any other value).
pub const DEFAULT_MAX_ITER: usize = 10_000;

/// What the linear deformation needs (shared by `adjoint` and `tangent`).
#[derive(Clone, Debug, Args)]
pub struct SensitivitySetup {
    /// The undeformed SU2 mesh (every marker's nodes are the boundary, prescribed, nodes), or
    /// a Plot3D grid (with --wall; the wall faces' nodes are the boundary).
    pub mesh: PathBuf,
    /// The deformation to differentiate (default: spring on SU2 meshes, tfi on Plot3D grids).
    #[arg(long, value_enum)]
    pub method: Option<SensitivityMethod>,
    /// The deformed mesh (e.g. `deform move`'s output, same nodes) whose boundary positions
    /// are the linearisation point of `--method quaternion`, `idw`, `rbf` and `elasticity`
    /// with `--steps` above 1 (default: the undeformed mesh).
    #[arg(long)]
    pub deformed: Option<PathBuf>,
    /// IDW weight exponent `p` in `(d_min / d)^p` (`--method idw-displacements` and `idw`, as
    /// `deform move --idw-exponent`).
    #[arg(long, default_value_t = DEFAULT_IDW_EXPONENT)]
    pub idw_exponent: f64,
    /// `--method idw`: the fast tree-based propagation with opening parameter THETA in
    /// [0, 1), as `deform move --idw-theta` (default: the exact sums).
    #[arg(long, value_name = "THETA")]
    pub idw_theta: Option<f64>,
    /// `--method idw` with --idw-theta: the largest accepted per-point error bound, as
    /// `deform move --idw-tolerance`.
    #[arg(
        long,
        value_name = "ETA",
        default_value_t = 0.1,
        requires = "idw_theta"
    )]
    pub idw_tolerance: f64,
    /// `--method elasticity`: Young's modulus per cell, as `deform move --stiffness`:
    /// inverse-volume (default), wall-distance (needs --wall-markers) or constant.
    #[arg(long, value_enum)]
    pub stiffness: Option<super::StiffnessArg>,
    /// `--method elasticity` with `--stiffness wall-distance`: the markers `deform move
    /// --marker` moved (the modulus is the inverse distance to their nodes).
    #[arg(long, num_args = 1.., value_name = "MARKER")]
    pub wall_markers: Vec<String>,
    /// `--method elasticity`: Poisson ratio, as `deform move --poisson` (default 0.3).
    #[arg(long, allow_hyphen_values = true)]
    pub poisson: Option<f64>,
    /// `--method elasticity`: load increments, as `deform move --steps` (the displacement in N
    /// equal parts; a `deform move --rotate` in steps follows its arc instead, another map).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub steps: u32,
    /// A symmetry marker whose nodes slide on its plane (a line in 2D) instead of staying
    /// fixed, as `deform move --slide` (repeat for several; with `adjoint --config` the
    /// config's MARKER_DEFORM_MESH_SYM_PLANE markers are added): `--method spring` and
    /// `elasticity` with one step.
    #[arg(long = "slide", value_name = "MARKER")]
    pub slide: Vec<String>,
    /// Relative residual tolerance of the spring (and elasticity) solves.
    #[arg(long, default_value_t = DEFAULT_TOL)]
    pub tol: f64,
    /// Strength threshold θ in [0, 1) of the solves' multigrid, as `deform move
    /// --amg-strength` (default 0.25). The derivative is the same to the tolerance for any θ;
    /// θ = 0 makes every spring strong.
    #[arg(long, value_name = "THETA")]
    pub amg_strength: Option<f64>,
    /// Iteration cap of the spring (and elasticity) solves.
    #[arg(long, default_value_t = DEFAULT_MAX_ITER)]
    pub max_iter: usize,
    /// The --rbf-* options of `--method rbf`.
    #[command(flatten)]
    pub rbf: super::RbfArgs,
    /// The wall and motion of a Plot3D grid's `deform move`.
    #[command(flatten)]
    pub grid: GridMotionArgs,
}

impl SensitivitySetup {
    /// `--method`, or the default for an SU2 mesh: spring (a Plot3D grid's run fills in `tfi`
    /// before anything reads it).
    pub fn method(&self) -> SensitivityMethod {
        self.method.unwrap_or(SensitivityMethod::Spring)
    }
}

/// `deform adjoint`.
#[derive(Clone, Debug, Args)]
pub struct AdjointArgs {
    /// Mesh and method.
    #[command(flatten)]
    pub setup: SensitivitySetup,
    /// The volume sensitivity dJ/dx at every mesh node: SU2_CFD_AD's adjoint restart in CSV
    /// (a header with "Sensitivity_x", "Sensitivity_y"[, "Sensitivity_z"] and optionally
    /// "PointID"), or plain rows `node dJ/dx dJ/dy [dJ/dz]` (0-based nodes, `%`/`#` comments;
    /// Plot3D grids: numbered block by block in Plot3D order, i fastest).
    #[arg(long)]
    pub sensitivity: PathBuf,
    /// Write the surface sensitivity of these markers' nodes (default: every marker).
    #[arg(long, num_args = 1..)]
    pub markers: Vec<String>,
    /// The surface sensitivity CSV: `node,x,y[,z],dJ/dx,dJ/dy[,dJ/dz]` per boundary node
    /// (Plot3D grids: per node of the moving --wall faces).
    #[arg(long)]
    pub out: PathBuf,
    /// An SU2 config with design variables (DV_KIND, DV_PARAM, DV_VALUE, DV_MARKER,
    /// OPT_RELAX_FACTOR; FFD boxes from the mesh file given here): also write dJ/dα of each
    /// variable to --grad-out, as SU2_DOT (TRANSLATION, ROTATION, HICKS_HENNE and the FFD
    /// variables of `deform su2`).
    #[arg(long, requires = "grad_out")]
    pub config: Option<PathBuf>,
    /// Where dJ/dα goes, in SU2_DOT's `of_grad.dat` form ("OBJECTIVE gradient" line, then one
    /// value per design variable, OUTPUT_PRECISION digits, 6 by default).
    #[arg(long, requires = "config")]
    pub grad_out: Option<PathBuf>,
}

/// `deform tangent`.
#[derive(Clone, Debug, Args)]
pub struct TangentArgs {
    /// Mesh and method.
    #[command(flatten)]
    pub setup: SensitivitySetup,
    /// The boundary perturbation: rows `node dx dy [dz]` (0-based, CSV or whitespace,
    /// `%`/`#` comments); boundary nodes not listed do not move. Plot3D grids: nodes of the
    /// moving --wall faces, numbered block by block in Plot3D order (i fastest).
    #[arg(long)]
    pub perturbation: PathBuf,
    /// The tangent field CSV: `node,dx,dy[,dz]` for every mesh node.
    #[arg(long)]
    pub out: PathBuf,
}
