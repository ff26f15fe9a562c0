//! Golden bits: every case of `deform_golden::CASES` must reproduce its committed hashes.
//!
//! On a mismatch the test prints, per differing case, the name, the old and the new values and
//! a ready-to-paste `expected_f64: 0x…, expected_f32: 0x…` line (see the `deform_golden`
//! crate documentation for when and how to update a hash deliberately).

use std::collections::BTreeSet;

use deform_golden::{Fnv, XorShift, CASES};

/// A hash as a Rust literal in the style of `golden/src/lib.rs` (`0x0123_4567_89ab_cdef`).
fn literal(h: u64) -> String {
    let hex = format!("{h:016x}");
    format!(
        "0x{}_{}_{}_{}",
        &hex[..4],
        &hex[4..8],
        &hex[8..12],
        &hex[12..]
    )
}

#[test]
fn every_golden_case_matches_its_committed_hash() {
    let mut failures = Vec::new();
    for case in CASES {
        let out = case.run();
        if !case.matches(&out) {
            failures.push(format!(
                "golden case `{}` changed:\n    f64: expected {:#018x}, got {:#018x}{}\n    f32: expected {:#018x}, got {:#018x}{}\n    new values: expected_f64: {}, expected_f32: {},",
                case.name,
                case.expected_f64,
                out.got_f64,
                if case.expected_f64 == out.got_f64 { "" } else { "  <- differs" },
                case.expected_f32,
                out.got_f32,
                if case.expected_f32 == out.got_f32 { "" } else { "  <- differs" },
                literal(out.got_f64),
                literal(out.got_f32),
            ));
        }
    }
    for f in &failures {
        eprintln!("{f}");
    }
    assert!(
        failures.is_empty(),
        "{} of {} golden cases differ (details above)",
        failures.len(),
        CASES.len()
    );
}

#[test]
fn golden_cases_are_deterministic_and_distinct() {
    // Running twice gives the same bits (no hidden state), names are unique, and no two
    // cases collide on a hash (which would hint at a case hashing nothing of its own).
    let mut names = BTreeSet::new();
    let mut owner = std::collections::BTreeMap::new();
    for case in CASES {
        assert!(names.insert(case.name), "duplicate case name {}", case.name);
        let a = case.run();
        let b = case.run();
        assert_eq!(a, b, "case {} is not deterministic", case.name);
        assert_ne!(
            a.got_f64,
            Fnv::new().finish(),
            "case {} hashes nothing",
            case.name
        );
        for h in [a.got_f64, a.got_f32] {
            let prev = owner.insert(h, case.name);
            assert!(
                prev.is_none() || prev == Some(case.name),
                "cases {} and {:?} share the hash {h:#x}",
                case.name,
                prev
            );
        }
    }
}

/// FNV-1a-64 written out independently (byte loop over the published constants), checked
/// against the published test vectors and against `deform_golden::Fnv`.
fn fnv1a64_reference(bytes: &[u8]) -> u64 {
    let mut h: u64 = 14695981039346656037;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(1099511628211);
    }
    h
}

#[test]
fn fnv_matches_an_independent_implementation() {
    // Published FNV-1a-64 vectors (Fowler/Noll/Vo test suite): "" and "a".
    assert_eq!(fnv1a64_reference(b""), 0xcbf29ce484222325);
    assert_eq!(fnv1a64_reference(b"a"), 0xaf63dc4c8601ec8c);
    let mut rng = XorShift::new(42);
    for len in 0..64 {
        let bytes: Vec<u8> = (0..len).map(|_| rng.next_u64() as u8).collect();
        let mut h = Fnv::new();
        h.bytes(&bytes);
        assert_eq!(h.finish(), fnv1a64_reference(&bytes));
    }
    // Scalars are hashed through their little-endian bit patterns.
    let mut h = Fnv::new();
    h.real(1.5f64);
    assert_eq!(
        h.finish(),
        fnv1a64_reference(&1.5f64.to_bits().to_le_bytes())
    );
    let mut h = Fnv::new();
    h.real(-0.0f32);
    assert_eq!(
        h.finish(),
        fnv1a64_reference(&u64::from((-0.0f32).to_bits()).to_le_bytes())
    );
}

#[test]
fn a_single_bit_flip_changes_the_hash() {
    // The property the golden test relies on: any output bit that changes changes the hash.
    let mut rng = XorShift::new(7);
    let values: Vec<f64> = (0..32).map(|_| rng.unit_f64()).collect();
    let hash = |v: &[f64]| {
        let mut h = Fnv::new();
        v.iter().for_each(|&x| h.real(x));
        h.finish()
    };
    let base = hash(&values);
    for i in 0..values.len() {
        for bit in 0..64 {
            let mut v = values.clone();
            v[i] = f64::from_bits(v[i].to_bits() ^ (1 << bit));
            assert_ne!(hash(&v), base, "flip of bit {bit} of value {i} not seen");
        }
    }
}

#[test]
fn xorshift_is_the_published_xorshift64_star() {
    // Independent step (Vigna, "An experimental exploration of Marsaglia's xorshift
    // generators, scrambled", 2016): shifts 12, 25, 27 and multiplier 2685821657736338717.
    let mut state: u64 = 0x1234_5678_9abc_def0;
    let mut rng = XorShift::new(state);
    for _ in 0..1000 {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        assert_eq!(rng.next_u64(), state.wrapping_mul(2685821657736338717));
    }
    let mut rng = XorShift::new(1);
    for _ in 0..1000 {
        let u = rng.unit_f64();
        assert!((0.0..1.0).contains(&u));
        assert!(rng.below(7) < 7);
    }
    assert_eq!(XorShift::new(0).below(0), 0);
}
