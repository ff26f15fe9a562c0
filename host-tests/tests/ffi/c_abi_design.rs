//! The design-variable functions of the C ABI (`dk_design_*`, f64 and f32): builds
//! `libdeform_kernel` (static and shared), compiles `ffi/tests/design.c` (Hicks–Henne bump
//! and surface bump with 1-based nodes, FFD evaluation of an affine lattice, an
//! FFD_CONTROL_POINT, both kinds of surface displacement, and bad input that must return its
//! status and write nothing), runs it, and checks that every check held. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

#[test]
fn design_variables_from_c_hold_their_checks() {
    for (link, exe) in [
        (Link::Static, "design_c_static"),
        (Link::Shared, "design_c_shared"),
    ] {
        assert_eq!(
            run_c_test("design", exe, link),
            "design: every check held\n",
            "{exe}"
        );
    }
}
