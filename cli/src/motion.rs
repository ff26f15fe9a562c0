//! How the moved boundary nodes move: the tool's one motion type, from the command line
//! (`--rotate`, `--translate`, `--displacements`, `--surface-positions`), from motion files
//! (`--motions`, rigid motions only) and for TFI on Plot3D walls (rigid motions only). A leaf
//! module: it depends on nothing in the crate, so formats and the engine can both use it.

/// A rigid rotation or translation of the moved nodes, or a prescribed displacement per node.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// Rigid rotation by `degrees` (counter-clockwise, right-hand rule) about `axis` through
    /// `center` (`None`: the centroid of the moved nodes).
    Rotate {
        /// Angle in degrees.
        degrees: f64,
        /// Axis (need not be unit length; never zero).
        axis: [f64; 3],
        /// Centre of rotation.
        center: Option<[f64; 3]>,
    },
    /// Rigid translation.
    Translate([f64; 3]),
    /// Prescribed displacement per node, ascending by node (other moved nodes stay put).
    Field(Vec<(u32, [f64; 3])>),
}

impl Motion {
    /// Whether the motion is rigid (a rotation or a translation), as motion files and TFI
    /// walls require.
    pub fn is_rigid(&self) -> bool {
        !matches!(self, Motion::Field(_))
    }
}
