//! Golden vectors: canonical inputs, the code that runs the kernel on them, and the committed
//! hashes of all output bits. `no_std` and allocation-free (it builds for
//! `thumbv7em-none-eabihf`), so the Cortex-M suite checks exactly the same constants as the
//! host test `host-tests/tests/golden.rs`.
//!
//! # How it works
//!
//! Every [`Case`] has two runners, one instantiated for `f64` and one for `f32`. A runner
//! builds its inputs from a fixed-seed [`XorShift`] generator (written here: no RNG crate, so
//! the inputs never change under a dependency update), calls kernel routines, and feeds every
//! output bit pattern (`to_bits`, widened to `u64`), every index and every error code into an
//! FNV-1a-64 [`Fnv`] hash. The hash is compared with the committed `expected_*` value: any
//! change in any output bit of any routine changes the hash (with overwhelming probability)
//! and the test fails, naming the case.
//!
//! Integer-only cases (the graph builders) have no scalar type; both of their runners are the
//! same function and both expected values are the same hash.
//!
//! # Adding a case
//!
//! 1. Write `fn my_case<T: Real>() -> u64` in a module (see [`quat_cases`]): build inputs with
//!    [`XorShift`], run the routine, hash every output with [`Fnv`] (use [`Fnv::result_quat`]
//!    style helpers for `Result`s so error outcomes are hashed too).
//! 2. Append `Case { name: "my_case", run_f64: my_case::<f64>, run_f32: my_case::<f32>,
//!    expected_f64: 0, expected_f32: 0 }` to [`CASES`].
//! 3. Run `cargo test -p deform-host-tests --test golden`: it fails and prints the computed
//!    values as a ready-to-paste `expected_f64: 0x…, expected_f32: 0x…` line. Paste it.
//!
//! # Updating a hash deliberately
//!
//! A hash may only change when an output bit changes *on purpose* (a more accurate formula, a
//! changed operation order, a fixed bug). Then:
//!
//! 1. Make sure the change is intended: the property and parity tests
//!    (`quat_properties`, `quat_parity`, …) must still pass, i.e. the new bits are still
//!    correct.
//! 2. Run `cargo test -p deform-host-tests --test golden`. It lists every case whose hash
//!    differs with its new values; paste them over the old `expected_*` constants in
//!    [`CASES`].
//! 3. Say in the commit message which cases changed and why. Never edit a hash by hand to a
//!    value that was not printed by the test, and never change the inputs of an existing case
//!    (add a new case instead), so old and new hashes stay comparable.
//!
//! Hashes are platform independent by construction: core arithmetic is IEEE 754 correctly
//! rounded everywhere, every transcendental function comes from `libm` (pure Rust), and the
//! kernel never uses fused multiply-add. The `micromath` feature is excluded from these
//! guarantees and must be off when the golden cases run.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod angle_rbf_sensitivity_cases;
pub mod design_cases;
pub mod graph_cases;
pub mod hash;
pub mod layer_cases;
pub mod mesh_cases;
pub mod method_cases;
pub mod quat_cases;
pub mod rng;
pub mod sensitivity_cases;

pub use hash::Fnv;
pub use rng::XorShift;

/// One golden case: a name, a runner per scalar type, and the committed hashes.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// Short unique name (printed when the hash differs).
    pub name: &'static str,
    /// Runs the case in `f64` and returns the FNV-1a-64 hash of all output bits.
    pub run_f64: fn() -> u64,
    /// Runs the case in `f32` and returns the FNV-1a-64 hash of all output bits.
    pub run_f32: fn() -> u64,
    /// The committed `f64` hash.
    pub expected_f64: u64,
    /// The committed `f32` hash.
    pub expected_f32: u64,
}

/// What running a [`Case`] produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The `f64` hash computed now.
    pub got_f64: u64,
    /// The `f32` hash computed now.
    pub got_f32: u64,
}

impl Case {
    /// Runs both runners.
    pub fn run(&self) -> Outcome {
        Outcome {
            got_f64: (self.run_f64)(),
            got_f32: (self.run_f32)(),
        }
    }

    /// `true` when `outcome` matches both committed hashes.
    pub fn matches(&self, outcome: &Outcome) -> bool {
        outcome.got_f64 == self.expected_f64 && outcome.got_f32 == self.expected_f32
    }
}

/// Every golden case. Append new cases at the end; never reorder or change existing inputs.
pub const CASES: &[Case] = &[
    Case {
        name: "quat_products",
        run_f64: quat_cases::products::<f64>,
        run_f32: quat_cases::products::<f32>,
        expected_f64: 0x0e33_b884_15f1_5812,
        expected_f32: 0xa852_4820_ebfc_62ab,
    },
    Case {
        name: "quat_rotate",
        run_f64: quat_cases::rotate::<f64>,
        run_f32: quat_cases::rotate::<f32>,
        expected_f64: 0x10e6_90fa_e485_8480,
        expected_f32: 0x27c7_df10_ee8f_ec64,
    },
    Case {
        name: "quat_rotation_arc",
        run_f64: quat_cases::rotation_arc::<f64>,
        run_f32: quat_cases::rotation_arc::<f32>,
        expected_f64: 0x32f8_f5af_40dc_b9fd,
        expected_f32: 0x7641_4789_b93e_c2a2,
    },
    Case {
        name: "quat_slerp_nlerp",
        run_f64: quat_cases::slerp::<f64>,
        run_f32: quat_cases::slerp::<f32>,
        expected_f64: 0x1a74_b6f5_c227_ad59,
        expected_f32: 0xf15e_3ca6_c31c_76b4,
    },
    Case {
        name: "quat_axis_angle",
        run_f64: quat_cases::axis_angle::<f64>,
        run_f32: quat_cases::axis_angle::<f32>,
        expected_f64: 0x9fd8_3051_bb71_ef6c,
        expected_f32: 0x77a7_f279_4f0e_0484,
    },
    Case {
        name: "quat_average",
        run_f64: quat_cases::average::<f64>,
        run_f32: quat_cases::average::<f32>,
        expected_f64: 0x08a0_9711_98a8_6a26,
        expected_f32: 0x5877_c87e_6470_05e7,
    },
    Case {
        name: "quat_normalize_inverse",
        run_f64: quat_cases::normalize::<f64>,
        run_f32: quat_cases::normalize::<f32>,
        expected_f64: 0x8643_35d0_c41f_0d90,
        expected_f32: 0x1405_470b_b1e8_4c1e,
    },
    Case {
        name: "graph_from_edges",
        run_f64: graph_cases::from_edges,
        run_f32: graph_cases::from_edges,
        expected_f64: 0x07b5_4d7d_d809_25e5,
        expected_f32: 0x07b5_4d7d_d809_25e5,
    },
    Case {
        name: "graph_from_cells",
        run_f64: graph_cases::from_cells,
        run_f32: graph_cases::from_cells,
        expected_f64: 0xef08_9098_5a12_f7d5,
        expected_f32: 0xef08_9098_5a12_f7d5,
    },
    Case {
        name: "graph_from_cells_diagonals",
        run_f64: graph_cases::from_cells_diagonals,
        run_f32: graph_cases::from_cells_diagonals,
        expected_f64: 0xdf78_d994_f188_b4b6,
        expected_f32: 0xdf78_d994_f188_b4b6,
    },
    Case {
        name: "spring_linear",
        run_f64: mesh_cases::spring_linear::<f64>,
        run_f32: mesh_cases::spring_linear::<f32>,
        expected_f64: 0x460f_11fc_9cee_775d,
        expected_f32: 0xe231_fda0_f3e4_f230,
    },
    Case {
        name: "spring_angle",
        run_f64: mesh_cases::spring_angle::<f64>,
        run_f32: mesh_cases::spring_angle::<f32>,
        expected_f64: 0xd678_4004_765b_ae76,
        expected_f32: 0x5d5b_5dfa_2734_807f,
    },
    Case {
        name: "quaternion_deformation",
        run_f64: mesh_cases::quaternion_deformation::<f64>,
        run_f32: mesh_cases::quaternion_deformation::<f32>,
        expected_f64: 0xce34_4464_000f_c07e,
        expected_f32: 0x8bee_19e2_2abe_f28e,
    },
    Case {
        name: "taubin_smoothing",
        run_f64: mesh_cases::taubin_smoothing::<f64>,
        run_f32: mesh_cases::taubin_smoothing::<f32>,
        expected_f64: 0xa9ea_d533_6889_ab72,
        expected_f32: 0x535c_c68c_cf72_d981,
    },
    Case {
        name: "spring_amg",
        run_f64: mesh_cases::spring_amg::<f64>,
        run_f32: mesh_cases::spring_amg::<f32>,
        expected_f64: 0x2605_83a7_0531_884c,
        expected_f32: 0xdd8b_e5f1_9ea3_e6e8,
    },
    Case {
        name: "spring_amg_strength",
        run_f64: mesh_cases::spring_amg_strength::<f64>,
        run_f32: mesh_cases::spring_amg_strength::<f32>,
        expected_f64: 0x2638_2be8_8e55_b1c5,
        expected_f32: 0x1b10_3d7f_a78e_d7b7,
    },
    Case {
        name: "spring_angle_amg",
        run_f64: mesh_cases::spring_angle_amg::<f64>,
        run_f32: mesh_cases::spring_angle_amg::<f32>,
        expected_f64: 0xaa05_af4d_ec6d_75fe,
        expected_f32: 0x8137_6c2f_1da4_cd36,
    },
    Case {
        name: "elasticity_2d",
        run_f64: method_cases::elasticity_2d::<f64>,
        run_f32: method_cases::elasticity_2d::<f32>,
        expected_f64: 0xcc13_796d_a282_5ee1,
        expected_f32: 0xc15c_97a7_f692_4dc5,
    },
    Case {
        name: "elasticity_3d",
        run_f64: method_cases::elasticity_3d::<f64>,
        run_f32: method_cases::elasticity_3d::<f32>,
        expected_f64: 0x986e_ef0a_6729_8eac,
        expected_f32: 0x4665_c8b2_643e_38d3,
    },
    Case {
        name: "rbf_2d",
        run_f64: method_cases::rbf_2d::<f64>,
        run_f32: method_cases::rbf_2d::<f32>,
        expected_f64: 0x5ffd_dd03_8ec1_7063,
        expected_f32: 0x41e7_09c6_dcce_3f5a,
    },
    Case {
        name: "rbf_3d",
        run_f64: method_cases::rbf_3d::<f64>,
        run_f32: method_cases::rbf_3d::<f32>,
        expected_f64: 0xa1cd_ffaa_c944_7465,
        expected_f32: 0xb0a7_9e50_3b30_4640,
    },
    Case {
        name: "quaternion_spring_tangent",
        run_f64: sensitivity_cases::quaternion_spring_tangent::<f64>,
        run_f32: sensitivity_cases::quaternion_spring_tangent::<f32>,
        expected_f64: 0x8ddf_8f7c_cf49_6d19,
        expected_f32: 0x5b11_74b6_53c0_7422,
    },
    Case {
        name: "quaternion_spring_adjoint",
        run_f64: sensitivity_cases::quaternion_spring_adjoint::<f64>,
        run_f32: sensitivity_cases::quaternion_spring_adjoint::<f32>,
        expected_f64: 0xa174_19ef_1a71_36e4,
        expected_f32: 0xf373_07bb_5508_82d6,
    },
    Case {
        name: "quaternion_tfi_tangent",
        run_f64: sensitivity_cases::quaternion_tfi_tangent::<f64>,
        run_f32: sensitivity_cases::quaternion_tfi_tangent::<f32>,
        expected_f64: 0x412d_c609_6218_c8da,
        expected_f32: 0x9db5_1531_60ac_99b2,
    },
    Case {
        name: "quaternion_tfi_adjoint",
        run_f64: sensitivity_cases::quaternion_tfi_adjoint::<f64>,
        run_f32: sensitivity_cases::quaternion_tfi_adjoint::<f32>,
        expected_f64: 0x5eb6_b77c_5482_d2d1,
        expected_f32: 0xb788_8270_d9d6_d0a9,
    },
    Case {
        name: "angle_spring_adjoint",
        run_f64: angle_rbf_sensitivity_cases::angle_spring_adjoint::<f64>,
        run_f32: angle_rbf_sensitivity_cases::angle_spring_adjoint::<f32>,
        expected_f64: 0x37c1_a2dd_1013_54f2,
        expected_f32: 0xc354_0272_6be0_90c1,
    },
    Case {
        name: "rbf_adjoint_tps",
        run_f64: angle_rbf_sensitivity_cases::rbf_adjoint_tps::<f64>,
        run_f32: angle_rbf_sensitivity_cases::rbf_adjoint_tps::<f32>,
        expected_f64: 0x0034_95fa_40ff_b0c5,
        expected_f32: 0x1453_0525_65f8_bd43,
    },
    Case {
        name: "rigid_wall_layer",
        run_f64: layer_cases::rigid_wall_layer::<f64>,
        run_f32: layer_cases::rigid_wall_layer::<f32>,
        expected_f64: 0xae88_e80e_3618_3821,
        expected_f32: 0x1048_e211_d3f3_a496,
    },
    Case {
        name: "design_adjoints",
        run_f64: design_cases::design_adjoints::<f64>,
        run_f32: design_cases::design_adjoints::<f32>,
        expected_f64: 0x56fa_9052_490b_a19b,
        expected_f32: 0x8011_7f06_d41a_341b,
    },
];
