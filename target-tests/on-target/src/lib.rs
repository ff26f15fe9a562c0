//! Support for the on-target tests: the defmt transport (semihosting, so QEMU prints the log on
//! stdout for `defmt-print`), a panic handler that exits QEMU with status 1 (so a failing test
//! fails `cargo test`), and small helpers shared by the test binaries.
#![no_std]

use cortex_m as _; // the critical-section implementation (single core)
use cortex_m_rt as _; // the vector table and reset handler
use defmt_semihosting as _; // the global defmt logger

/// Any panic (a failed `assert!` in a test) ends the QEMU process with exit status 1.
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic: {}", defmt::Display2Format(info));
    semihosting::process::exit(1)
}

/// `defmt::panic!` and failed `defmt::assert!` end QEMU with status 1 too.
#[defmt::panic_handler]
fn defmt_panic() -> ! {
    semihosting::process::exit(1)
}

pub mod mesh;

/// Parameter structs of the C ABI over borrowed slices, for the `c_abi*` tests.
pub mod abi {
    use deform_kernel_ffi::graph::{dk_cells, dk_graph};

    /// A `dk_graph` borrowing `offsets` and `targets` (each passed with its own length).
    pub fn graph(offsets: &[u32], targets: &[u32]) -> dk_graph {
        dk_graph {
            offsets: offsets.as_ptr(),
            offsets_len: offsets.len(),
            targets: targets.as_ptr(),
            targets_len: targets.len(),
        }
    }

    /// A `dk_cells` borrowing the three arrays (each passed with its own length).
    pub fn cells(offsets: &[u32], nodes: &[u32], kinds: &[u8]) -> dk_cells {
        dk_cells {
            offsets: offsets.as_ptr(),
            offsets_len: offsets.len(),
            nodes: nodes.as_ptr(),
            nodes_len: nodes.len(),
            kinds: kinds.as_ptr(),
            kinds_len: kinds.len(),
        }
    }
}

use deform_kernel::Real;

/// Largest `|a − b|` over all components of two point/value lists (∞ on a length mismatch).
pub fn max_diff<T: Real, const V: usize>(a: &[[T; V]], b: &[[T; V]]) -> T {
    if a.len() != b.len() {
        return T::INFINITY;
    }
    let mut m = T::ZERO;
    for (x, y) in a.iter().zip(b) {
        for (&p, &q) in x.iter().zip(y) {
            m = m.max((p - q).abs());
        }
    }
    m
}

/// Largest `|x|` over all components.
pub fn max_abs<T: Real, const V: usize>(a: &[[T; V]]) -> T {
    a.iter()
        .flat_map(|v| v.iter())
        .fold(T::ZERO, |m, &x| m.max(x.abs()))
}

/// `true` when both lists have the same bits everywhere.
pub fn same_bits<T: Real, const V: usize>(a: &[[T; V]], b: &[[T; V]]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.iter()
                .zip(y)
                .all(|(p, q)| p.to_bits_u64() == q.to_bits_u64())
        })
}

/// `"f32"` or `"f64"` for log lines.
pub fn precision<T: Real>() -> &'static str {
    if T::MANTISSA_DIGITS == 24 {
        "f32"
    } else {
        "f64"
    }
}
