//! Link-time proof that deform-kernel is panic-free.
//!
//! Every public kernel entry point is called with [`core::hint::black_box`] inputs (so the
//! optimiser cannot fold them) and its outputs are black-boxed (so it cannot drop the calls).
//! The `#[panic_handler]` calls [`deform_kernel_panic_path_survived`], an `extern "C"` function
//! that is deliberately defined nowhere: if any panic path (bounds check, overflow check,
//! `unwrap`, `expect`, `unreachable!`, division by zero, ...) survives release optimisation
//! (fat LTO, one codegen unit, `panic = "abort"`), the handler is reachable, the symbol is
//! referenced and the link fails with
//! `undefined reference to deform_kernel_panic_path_survived`.
//!
//! Build from `target-tests/`: `cargo build --release -p panic-check` (it must link), and
//! `cargo build --release -p panic-check --features deliberate-panic` (it must NOT link, and
//! for that reason only). `cargo xtask ci` runs both.
//!
//! Each kernel module has its own file with an `exercise()` function; a new public entry
//! point is not proven panic-free until it is called from there. When the link fails,
//! `cargo xtask panic-locate` lists the functions that still reach the panic handler.
//!
//! Scope of the proof: the shipped release profile, where integer overflow wraps
//! (`overflow-checks = false`, as in every release build of the kernel and the C library), so
//! arithmetic overflow is not a panic path here; bounds checks, `unwrap`/`expect`, slice
//! splitting, division by zero and explicit panics are. Derived `Debug` impls and float
//! formatting are core's code and are not called (core's `<str as Debug>` keeps panic paths).
//! The kernel is built with its `glam` and `defmt` features (their impls are called here);
//! the `micromath` feature is checked by a second build.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m as _;
use cortex_m_rt::entry;

mod amg;
mod deformation;
mod foundation;
mod plan;
mod quality;
mod slide;
mod spring;
mod taubin;

#[entry]
fn main() -> ! {
    foundation::exercise();
    spring::exercise();
    amg::exercise();
    quality::exercise();
    taubin::exercise();
    deformation::exercise();
    slide::exercise();
    plan::exercise();
    #[cfg(feature = "deliberate-panic")]
    deliberate_panic();
    loop {
        cortex_m::asm::wfi();
    }
}

/// Indexes a black-boxed slice at a black-boxed position: the bounds check cannot be proven
/// away, so this variant must fail to link.
#[cfg(feature = "deliberate-panic")]
#[inline(never)]
fn deliberate_panic() {
    let values: &[u32] = black_box(&[1, 2, 3]);
    let index: usize = black_box(7);
    black_box(values[index]);
}

#[cfg(not(feature = "locate"))]
extern "C" {
    /// Deliberately undefined: referencing it makes the link fail.
    fn deform_kernel_panic_path_survived() -> !;
}

/// With `locate`, the panic target exists so the binary links; its callers are the surviving
/// panic paths.
#[cfg(feature = "locate")]
#[inline(never)]
#[no_mangle]
extern "C" fn deform_kernel_panic_path_survived() -> ! {
    cortex_m::asm::udf()
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    black_box(info);
    #[cfg(not(feature = "locate"))]
    // SAFETY: never executed in a binary that links; the symbol exists nowhere.
    unsafe {
        deform_kernel_panic_path_survived()
    }
    #[cfg(feature = "locate")]
    deform_kernel_panic_path_survived()
}

/// defmt logger that discards everything: lets the kernel's `defmt::Format` impls be called.
#[defmt::global_logger]
struct DiscardLogger;

// SAFETY: single-core, no interrupts use it; every method is a no-op on opaque data.
unsafe impl defmt::Logger for DiscardLogger {
    fn acquire() {}
    unsafe fn flush() {}
    unsafe fn release() {}
    unsafe fn write(bytes: &[u8]) {
        black_box(bytes);
    }
}
