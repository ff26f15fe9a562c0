//! Golden bit parity: every case of `deform-golden` gives, on the Cortex-M4F (hardware f32,
//! soft-float f64), exactly the hashes committed from the host.
#![no_std]
#![no_main]

use deform_on_target as _;

#[defmt_test::tests]
mod tests {
    use deform_golden::CASES;

    #[test]
    fn every_golden_case_matches_the_host_bits() {
        let mut failed = 0u32;
        for case in CASES {
            let got = case.run();
            if case.matches(&got) {
                defmt::info!("golden {=str}: ok", case.name);
            } else {
                failed += 1;
                defmt::error!(
                    "golden {=str}: f64 {=u64:#x} (host {=u64:#x}), f32 {=u64:#x} (host {=u64:#x})",
                    case.name,
                    got.got_f64,
                    case.expected_f64,
                    got.got_f32,
                    case.expected_f32
                );
            }
        }
        defmt::assert_eq!(failed, 0, "golden cases differ from the host");
    }

    #[test]
    fn there_are_golden_cases() {
        defmt::assert!(CASES.len() >= 5);
    }
}
