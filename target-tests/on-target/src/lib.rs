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
