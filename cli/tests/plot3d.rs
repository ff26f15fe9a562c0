//! Plot3D reader/writer: every layout round-trips bitwise, detection, malformed input.

mod common;

use common::Rng;
use deform_cli::formats::plot3d::{
    parse_plot3d, write_plot3d, Encoding, Endian, Plot3dBlock, Plot3dGrid, Plot3dLayout,
    Plot3dOptions, Precision,
};
use deform_cli::formats::{FormatErrorKind, Location};

fn grid(dim: usize, nblocks: usize, single: bool, iblank: bool) -> Plot3dGrid {
    let mut rng = Rng(7 + dim as u64 * 31 + nblocks as u64);
    let shapes: [[usize; 3]; 3] = if dim == 2 {
        [[4, 3, 1], [5, 2, 1], [2, 2, 1]]
    } else {
        [[3, 2, 2], [2, 2, 4], [2, 3, 2]]
    };
    let blocks = shapes
        .iter()
        .take(nblocks)
        .enumerate()
        .map(|(b, &dims)| {
            let n = dims[0] * dims[1] * dims[2];
            let points = (0..n)
                .map(|p| {
                    let mut v = [p as f64 + rng.real(), b as f64 - rng.real() * 1e-7, 0.0];
                    if dim == 3 {
                        v[2] = rng.real() * 1e5;
                    }
                    if single {
                        v = v.map(|x| x as f32 as f64);
                    }
                    v
                })
                .collect();
            let iblank = iblank.then(|| (0..n).map(|p| (p % 3) as i32 - 1).collect());
            Plot3dBlock {
                dims,
                points,
                iblank,
            }
        })
        .collect();
    Plot3dGrid { dim, blocks }
}

fn all_layouts() -> Vec<Plot3dLayout> {
    let mut encs = vec![Encoding::Ascii];
    for endian in [Endian::Little, Endian::Big] {
        for precision in [Precision::Single, Precision::Double] {
            for records in [true, false] {
                encs.push(Encoding::Binary {
                    endian,
                    precision,
                    records,
                });
            }
        }
    }
    let mut out = Vec::new();
    for encoding in encs {
        for dim in [2, 3] {
            for multi_block in [false, true] {
                for iblank in [false, true] {
                    out.push(Plot3dLayout {
                        encoding,
                        dim,
                        multi_block,
                        iblank,
                    });
                }
            }
        }
    }
    out
}

fn write(g: &Plot3dGrid, l: &Plot3dLayout) -> Vec<u8> {
    let mut v = Vec::new();
    write_plot3d(g, l, &mut v).expect("write to a Vec");
    v
}

#[test]
fn every_layout_round_trips_bitwise_with_auto_detection() {
    let layouts = all_layouts();
    assert_eq!(layouts.len(), 72);
    for l in &layouts {
        let single = matches!(
            l.encoding,
            Encoding::Binary {
                precision: Precision::Single,
                ..
            }
        );
        for nblocks in if l.multi_block { vec![1, 3] } else { vec![1] } {
            let g = grid(l.dim, nblocks, single, l.iblank);
            let bytes = write(&g, l);
            let (back, detected) = parse_plot3d(&bytes, &Plot3dOptions::default())
                .unwrap_or_else(|e| panic!("{l}: {e}"));
            assert_eq!(&detected, l, "layout detection");
            assert_eq!(back, g, "{l}");
            for (a, b) in back.blocks.iter().zip(&g.blocks) {
                for (p, q) in a.points.iter().zip(&b.points) {
                    assert_eq!(p.map(f64::to_bits), q.map(f64::to_bits), "{l}");
                }
            }
            assert_eq!(write(&back, &detected), bytes, "{l}: second write differs");
        }
    }
}

#[test]
fn fortran_record_layout_bytes() {
    // 2D single block 2x1, f32 little endian with records: [8][2 1][8] [16][x0 x1 y0 y1][16].
    let g = Plot3dGrid {
        dim: 2,
        blocks: vec![Plot3dBlock {
            dims: [2, 1, 1],
            points: vec![[1.0, 2.0, 0.0], [3.0, 4.0, 0.0]],
            iblank: None,
        }],
    };
    let l = Plot3dLayout {
        encoding: Encoding::Binary {
            endian: Endian::Little,
            precision: Precision::Single,
            records: true,
        },
        dim: 2,
        multi_block: false,
        iblank: false,
    };
    let b = write(&g, &l);
    let mut expect = Vec::new();
    for i in [8i32, 2, 1, 8, 16] {
        expect.extend_from_slice(&i.to_le_bytes());
    }
    for x in [1.0f32, 3.0, 2.0, 4.0] {
        expect.extend_from_slice(&x.to_le_bytes());
    }
    expect.extend_from_slice(&16i32.to_le_bytes());
    assert_eq!(b, expect);
}

#[test]
fn fortran_style_ascii_is_read() {
    let text = " 1\n 2 2\n 0.0D+00 1.0D+00 0.0 1.0\n 0.0 0.0 2.5d0 2.5E0\n";
    let (g, l) = parse_plot3d(text.as_bytes(), &Plot3dOptions::default()).expect("valid");
    assert_eq!(l.encoding, Encoding::Ascii);
    assert_eq!((l.dim, l.multi_block), (2, true));
    assert_eq!(g.blocks[0].points[3], [1.0, 2.5, 0.0]);
}

#[test]
fn ambiguous_files_ask_for_options() {
    // "2 2" + 8 integers: a 2D single block, or a 2-block header... only one fits, but integer
    // coordinates make 2D-with-header and 3D readings possible; the options settle it.
    let text = "1\n2 2 1\n0 1 0 1\n0 0 1 1\n0 0 0 0\n";
    let r = parse_plot3d(text.as_bytes(), &Plot3dOptions::default());
    match r {
        Ok((_, l)) => assert_eq!((l.dim, l.multi_block), (3, true)),
        Err(e) => assert!(matches!(e.kind, FormatErrorKind::Ambiguous { .. }), "{e}"),
    }
    let opts = Plot3dOptions {
        dim: Some(3),
        multi_block: Some(true),
        iblank: Some(false),
        ..Default::default()
    };
    let (g, _) = parse_plot3d(text.as_bytes(), &opts).expect("with options");
    assert_eq!(g.blocks[0].dims, [2, 2, 1]);
}

fn records_file() -> Vec<u8> {
    let g = grid(3, 2, false, false);
    let l = Plot3dLayout {
        encoding: Encoding::Binary {
            endian: Endian::Big,
            precision: Precision::Double,
            records: true,
        },
        dim: 3,
        multi_block: true,
        iblank: false,
    };
    write(&g, &l)
}

#[test]
fn truncated_binary_names_the_byte() {
    let b = records_file();
    let cut = &b[..b.len() - 100];
    let e = parse_plot3d(cut, &Plot3dOptions::default()).expect_err("truncated");
    let msg = e.to_string();
    assert!(msg.contains("unexpected end of file"), "{msg}");
    assert!(msg.contains("block 2 data"), "{msg}");
    assert!(msg.contains("big-endian"), "{msg}");
    assert!(matches!(e.location, Location::Byte(_)), "{msg}");
}

#[test]
fn bad_record_marker() {
    let mut b = records_file();
    // Block 1 record marker (after nb record 12 bytes and dims record 4+24+4 bytes).
    b[44 + 3] ^= 0x10;
    let e = parse_plot3d(&b, &Plot3dOptions::default()).expect_err("bad marker");
    assert_eq!(e.location, Location::Byte(44), "{e}");
    assert!(e.to_string().contains("record marker"), "{e}");
}

#[test]
fn nan_in_binary_and_ascii() {
    let mut b = records_file();
    // First x of block 1 starts at byte 48.
    b[48..56].copy_from_slice(&f64::NAN.to_be_bytes());
    let e = parse_plot3d(&b, &Plot3dOptions::default()).expect_err("NaN");
    assert_eq!(e.location, Location::Byte(48));
    assert!(
        e.to_string()
            .contains("x of point 0 of block 1 is not a finite number"),
        "{e}"
    );
    let text = "2 2\n0 1 0 NaN\n0 0 1 1\n";
    let e = parse_plot3d(text.as_bytes(), &Plot3dOptions::default()).expect_err("NaN");
    assert_eq!(e.location, Location::Line(2));
    assert!(
        e.to_string()
            .contains("x of point 3 of block 1 is not a finite number"),
        "{e}"
    );
}

#[test]
fn wrong_counts_in_ascii() {
    let text = "2 3\n0 1 0 1\n0 0 1 1\n";
    let e = parse_plot3d(text.as_bytes(), &Plot3dOptions::default()).expect_err("short");
    assert!(e.to_string().contains("line 3"), "{e}");
    assert!(e.to_string().contains("values after the dimensions"), "{e}");
    let opts = Plot3dOptions {
        dim: Some(2),
        multi_block: Some(false),
        iblank: Some(false),
        ..Default::default()
    };
    let e = parse_plot3d(text.as_bytes(), &opts).expect_err("short");
    assert_eq!(
        e.to_string(),
        "line 3: expected 12 values after the dimensions of 1 block(s), found 8 (the file ends early) (reading as the closest layout: 2D ASCII, single block, no iblank)"
    );
}

#[test]
fn garbage_and_empty() {
    let e = parse_plot3d(b"", &Plot3dOptions::default()).expect_err("empty");
    assert!(e.to_string().contains("empty"), "{e}");
    let g: Vec<u8> = (0..999u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    let e = parse_plot3d(&g, &Plot3dOptions::default()).expect_err("garbage");
    assert!(matches!(e.kind, FormatErrorKind::NoLayout { .. }), "{e}");
    let e = parse_plot3d(b"hello world", &Plot3dOptions::default()).expect_err("text");
    assert_eq!(e.location, Location::Line(1));
}

#[test]
fn huge_dimensions_do_not_allocate() {
    let mut b = Vec::new();
    for i in [12i32, i32::MAX, i32::MAX, i32::MAX, 12] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    let e = parse_plot3d(&b, &Plot3dOptions::default()).expect_err("huge");
    assert!(!e.to_string().is_empty());
    let e = parse_plot3d(
        b"1000000000 1000000000 1000000000\n1 2 3",
        &Plot3dOptions::default(),
    )
    .expect_err("huge ascii");
    assert!(!e.to_string().is_empty());
}

#[test]
fn random_mutations_never_panic() {
    let mut rng = Rng(99);
    let bases: Vec<Vec<u8>> = all_layouts()
        .iter()
        .step_by(5)
        .map(|l| {
            write(
                &grid(l.dim, 1 + usize::from(l.multi_block), false, l.iblank),
                l,
            )
        })
        .collect();
    for round in 0..2000 {
        let mut b = bases[round % bases.len()].clone();
        for _ in 0..1 + rng.below(3) {
            if b.is_empty() {
                break;
            }
            let i = rng.below(b.len());
            match rng.below(3) {
                0 => b[i] = rng.next() as u8,
                1 => b.truncate(i),
                _ => {
                    b.remove(i);
                }
            }
        }
        let _ = parse_plot3d(&b, &Plot3dOptions::default());
    }
}
