//! Target 8: the C ABI with arbitrary lengths (never more than the real buffer), NULL pointers
//! and index bases: no crash, a documented status, outputs untouched unless `DK_OK`, and on
//! success the same bits as the Rust API.
#![no_main]

use std::ptr;

use arbitrary::Arbitrary;
use deform_kernel::{graph_from_edges, Quat};
use dk_ffi::dk_status;
use dk_ffi::graph::dk_graph_from_edges;
use dk_ffi::quat::{dk_quat_average, dk_quat_mul, dk_quat_rotate_points};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    node_count: u8,
    edges: Vec<u32>,
    edges_len_cut: u8,
    index_base: u8,
    offsets_len: u8,
    targets_len: u8,
    nulls: u8,
    quats: Vec<f64>,
    quats_len_cut: u8,
    points: Vec<f64>,
}

const SENTINEL: u32 = 0x5a5a_5a5a;

fn ptr_or_null<T>(p: *const T, null: bool) -> *const T {
    if null {
        ptr::null()
    } else {
        p
    }
}

fuzz_target!(|inp: Input| {
    // --- dk_graph_from_edges ---
    let edges_len = inp.edges.len().saturating_sub(inp.edges_len_cut as usize);
    let mut offsets = vec![SENTINEL; inp.offsets_len as usize];
    let mut targets = vec![SENTINEL; inp.targets_len as usize];
    let mut used = usize::MAX;
    let base = (inp.index_base % 3) as u32;
    // SAFETY: every pointer is valid for the length passed with it (or NULL).
    let s = unsafe {
        dk_graph_from_edges(
            inp.node_count as usize,
            ptr_or_null(inp.edges.as_ptr(), inp.nulls & 1 != 0),
            edges_len,
            base,
            if inp.nulls & 2 != 0 {
                ptr::null_mut()
            } else {
                offsets.as_mut_ptr()
            },
            offsets.len(),
            targets.as_mut_ptr(),
            targets.len(),
            if inp.nulls & 4 != 0 {
                ptr::null_mut()
            } else {
                &mut used
            },
        )
    };
    if s == dk_status::DK_OK {
        assert!(base <= 1 && edges_len % 2 == 0);
        let pairs: Vec<[u32; 2]> = inp.edges[..edges_len]
            .chunks_exact(2)
            .map(|c| [c[0].wrapping_sub(base), c[1].wrapping_sub(base)])
            .collect();
        let mut o = vec![0u32; offsets.len()];
        let mut t = vec![0u32; targets.len()];
        let n = graph_from_edges(inp.node_count as usize, &pairs, &mut o, &mut t).unwrap();
        assert_eq!(n, used);
        assert_eq!(o, offsets);
        assert_eq!(&t[..n], &targets[..n]);
    } else {
        assert!(
            offsets.iter().chain(&targets).all(|&x| x == SENTINEL),
            "{s:?}"
        );
        assert_eq!(used, usize::MAX);
    }

    // --- dk_quat_mul / dk_quat_average / dk_quat_rotate_points ---
    let q4: Vec<f64> = inp.quats.iter().copied().chain([1.0; 8]).take(8).collect();
    let mut out = [f64::from_bits(0x7ff0_dead_0000_0001); 4];
    let before = out.map(f64::to_bits);
    // SAFETY: 4 scalars each, or NULL.
    let s = unsafe {
        dk_quat_mul(
            ptr_or_null(q4.as_ptr(), inp.nulls & 8 != 0),
            q4[4..].as_ptr(),
            out.as_mut_ptr(),
        )
    };
    if s == dk_status::DK_OK {
        let want = Quat::from_array([q4[0], q4[1], q4[2], q4[3]])
            * Quat::from_array([q4[4], q4[5], q4[6], q4[7]]);
        assert_eq!(out.map(f64::to_bits), want.to_array().map(f64::to_bits));
    } else {
        assert_eq!(out.map(f64::to_bits), before);
    }
    let quats_len = inp.quats.len().saturating_sub(inp.quats_len_cut as usize);
    let mut out = [f64::from_bits(0x7ff0_dead_0000_0001); 4];
    // SAFETY: `quats_len` <= quats.len(); weights NULL with length 0.
    let s = unsafe {
        dk_quat_average(
            ptr_or_null(inp.quats.as_ptr(), inp.nulls & 16 != 0),
            quats_len,
            ptr::null(),
            0,
            out.as_mut_ptr(),
        )
    };
    if s != dk_status::DK_OK {
        assert_eq!(out.map(f64::to_bits), before);
    } else {
        assert!(out.iter().all(|x| x.is_finite()));
    }
    let mut rotated = vec![-0.0f64; inp.points.len()];
    // SAFETY: both buffers have `points.len()` elements.
    let s = unsafe {
        dk_quat_rotate_points(
            q4.as_ptr(),
            inp.points.as_ptr(),
            inp.points.len(),
            rotated.as_mut_ptr(),
            rotated.len(),
        )
    };
    if s != dk_status::DK_OK {
        assert!(rotated.iter().all(|x| x.to_bits() == (-0.0f64).to_bits()));
    }
});
