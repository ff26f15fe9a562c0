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
    /// (its derivative is the kernel's `quaternion::deform_idw_tangent`/`_adjoint`).
    IdwDisplacements,
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
}

/// What the linear deformation needs (shared by `adjoint` and `tangent`).
#[derive(Clone, Debug, Args)]
pub struct SensitivitySetup {
    /// The undeformed SU2 mesh. Every marker's nodes are the boundary (prescribed) nodes.
    pub mesh: PathBuf,
    /// The deformation to differentiate.
    #[arg(long, value_enum, default_value = "spring")]
    pub method: SensitivityMethod,
    /// The deformed mesh (e.g. `deform move`'s output, same nodes) whose boundary positions
    /// are the linearisation point of `--method quaternion` and of `--method rbf` (default: the
    /// undeformed mesh).
    #[arg(long)]
    pub deformed: Option<PathBuf>,
    /// IDW weight exponent `p` in `(d_min / d)^p` (`--method idw-displacements`).
    #[arg(long, default_value_t = 2.0)]
    pub idw_exponent: f64,
    /// Relative residual tolerance of the spring solve.
    #[arg(long, default_value_t = 1e-12)]
    pub tol: f64,
    /// Iteration cap of the spring solve.
    #[arg(long, default_value_t = 10_000)]
    pub max_iter: usize,
    /// The --rbf-* options of `--method rbf`.
    #[command(flatten)]
    pub rbf: super::RbfArgs,
}

/// `deform adjoint`.
#[derive(Clone, Debug, Args)]
pub struct AdjointArgs {
    /// Mesh and method.
    #[command(flatten)]
    pub setup: SensitivitySetup,
    /// The volume sensitivity dJ/dx at every mesh node: SU2_CFD_AD's adjoint restart in CSV
    /// (a header with "Sensitivity_x", "Sensitivity_y"[, "Sensitivity_z"] and optionally
    /// "PointID"), or plain rows `node dJ/dx dJ/dy [dJ/dz]` (0-based nodes, `%`/`#` comments).
    #[arg(long)]
    pub sensitivity: PathBuf,
    /// Write the surface sensitivity of these markers' nodes (default: every marker).
    #[arg(long, num_args = 1..)]
    pub markers: Vec<String>,
    /// The surface sensitivity CSV: `node,x,y[,z],dJ/dx,dJ/dy[,dJ/dz]` per boundary node.
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
    /// `%`/`#` comments); boundary nodes not listed do not move.
    #[arg(long)]
    pub perturbation: PathBuf,
    /// The tangent field CSV: `node,dx,dy[,dz]` for every mesh node.
    #[arg(long)]
    pub out: PathBuf,
}
