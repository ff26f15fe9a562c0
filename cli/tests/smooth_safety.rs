//! `deform smooth` on grids where the old tool wrote wrong results with exit 0: line ends,
//! O-grid seams and block interfaces stay bitwise where they were, uniform lines stay uniform,
//! and cells that smoothing flips are refused (or, with --allow-folds, written and counted).
//! Flipped cells are counted here with independent code (corner cross products on the
//! written file, parsed with a few lines of whitespace splitting).

mod common;

use std::path::Path;

use common::{deform, tmp_dir};
use serde_json::Value;

type Block = (usize, usize, Vec<[f64; 2]>);

/// A multi-block 2D ASCII Plot3D file (always with the block count, so the reader cannot
/// confuse layouts).
fn write_p2d(path: &Path, blocks: &[Block]) {
    let mut s = format!("{}\n", blocks.len());
    for (ni, nj, _) in blocks {
        s.push_str(&format!("{ni} {nj}\n"));
    }
    for (_, _, pts) in blocks {
        for c in 0..2 {
            let v: Vec<String> = pts.iter().map(|p| format!("{:?}", p[c])).collect();
            s.push_str(&v.join(" "));
            s.push('\n');
        }
    }
    std::fs::write(path, s).unwrap();
}

fn read_p2d(path: &Path) -> Vec<Block> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut it = text.split_whitespace();
    let mut next = || it.next().unwrap().to_string();
    let nb: usize = next().parse().unwrap();
    let dims: Vec<(usize, usize)> = (0..nb)
        .map(|_| (next().parse().unwrap(), next().parse().unwrap()))
        .collect();
    dims.into_iter()
        .map(|(ni, nj)| {
            let n = ni * nj;
            let x: Vec<f64> = (0..n).map(|_| next().parse().unwrap()).collect();
            let y: Vec<f64> = (0..n).map(|_| next().parse().unwrap()).collect();
            (ni, nj, x.into_iter().zip(y).map(|(a, b)| [a, b]).collect())
        })
        .collect()
}

fn json(dir: &Path, args: &[&str]) -> Value {
    let mut v = vec!["--json"];
    v.extend_from_slice(args);
    let o = deform(dir, &v);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

/// Smallest corner cross product of each quad (i-fastest cells), times `sense` (−1 for a
/// block whose cells turn clockwise).
fn min_corners(b: &Block, sense: f64) -> Vec<f64> {
    let (ni, nj, p) = b;
    let mut out = Vec::new();
    for j in 0..nj - 1 {
        for i in 0..ni - 1 {
            let q = [
                p[i + ni * j],
                p[i + 1 + ni * j],
                p[i + 1 + ni * (j + 1)],
                p[i + ni * (j + 1)],
            ];
            let m = (0..4)
                .map(|c| {
                    let (a, n, v) = (q[c], q[(c + 1) % 4], q[(c + 3) % 4]);
                    sense * ((n[0] - a[0]) * (v[1] - a[1]) - (n[1] - a[1]) * (v[0] - a[0]))
                })
                .fold(f64::INFINITY, f64::min);
            out.push(m);
        }
    }
    out
}

/// An annulus sector whose two wall lines are clustered toward the start and the outer lines
/// uniform: smoothing along i pulls the thin first layer apart around the curve.
fn fan() -> Block {
    let (ni, nj) = (41, 8);
    let radii: Vec<f64> = [1.0, 1.001]
        .into_iter()
        .chain((0..nj - 2).map(|k| 1.3 + 0.2 * k as f64))
        .collect();
    let mut pts = Vec::new();
    for (j, r) in radii.iter().enumerate() {
        for i in 0..ni {
            let t = i as f64 / (ni - 1) as f64;
            let th = 1.2 * if j <= 1 { t.powf(1.5) } else { t };
            pts.push([r * th.cos(), r * th.sin()]);
        }
    }
    (ni, nj, pts)
}

/// The fan's i runs counter-clockwise and its j outward: its cells turn clockwise.
const SENSE: f64 = -1.0;

#[test]
fn flipped_cells_are_refused_or_written_and_counted() {
    let d = tmp_dir("smooth-flips");
    let input = fan();
    assert!(
        min_corners(&input, SENSE).iter().all(|&m| m > 0.0),
        "the input is valid"
    );
    write_p2d(&d.join("fan.p2dfmt.xy"), std::slice::from_ref(&input));
    let args = [
        "smooth",
        "fan.p2dfmt.xy",
        "--direction",
        "i",
        "--iterations",
        "5",
    ];
    let mut refuse = args.to_vec();
    refuse.extend(["--out", "out.xy"]);
    let o = deform(&d, &refuse);
    let err = String::from_utf8_lossy(&o.stderr);
    // Exit 4: the failure policy `move` shares (issue 31 item 5).
    assert_eq!(o.status.code(), Some(4), "{err}");
    for needle in [
        "block 1",
        "flips",
        "cell i=",
        "after iteration",
        "nothing was written",
    ] {
        assert!(err.contains(needle), "{needle:?} in {err}");
    }
    assert!(!d.join("out.xy").exists());

    let mut allow = args.to_vec();
    allow.extend(["--out", "allowed.xy", "--allow-folds"]);
    let r = json(&d, &allow);
    let written = read_p2d(&d.join("allowed.xy"));
    let independent = min_corners(&input, SENSE)
        .iter()
        .zip(min_corners(&written[0], SENSE))
        .filter(|(&b, a)| b > 0.0 && *a <= 0.0)
        .count();
    assert!(independent > 0);
    assert_eq!(r["flipped_cells"], independent, "{r}");
}

/// A full O-grid (i around, j outward) whose seam i = 0 / i = ni − 1 is stored twice, with a
/// noisy radial distribution.
fn ogrid() -> Block {
    let (ni, nj) = (33, 12);
    let mut pts = vec![[0.0; 2]; ni * nj];
    for j in 0..nj {
        for i in 0..ni - 1 {
            let noise = ((i * 7 + j * 3) % 5) as f64 * 0.02;
            let r = 1.0 + 0.15 * (j as f64 + if j > 0 && j + 1 < nj { noise } else { 0.0 });
            let th = std::f64::consts::TAU * i as f64 / (ni - 1) as f64;
            pts[i + ni * j] = [r * th.cos(), 0.6 * r * th.sin()];
        }
        pts[ni - 1 + ni * j] = pts[ni * j];
    }
    (ni, nj, pts)
}

#[test]
fn line_ends_seams_and_interfaces_stay_closed_and_bitwise() {
    let d = tmp_dir("smooth-seams");
    let og = ogrid();
    // A second block glued to the outer boundary j = nj − 1 of the O-grid: its j = 0 line is
    // the same points, its lines run further out with another noise.
    let (ni, nj, p) = &og;
    let mut outer = Vec::new();
    for j in 0..6 {
        for i in 0..*ni {
            let base = p[i + ni * (nj - 1)];
            let noise = (((i % (ni - 1)) * 5 + j) % 3) as f64 * 0.03;
            let f = 1.0 + 0.1 * j as f64 + if j > 0 && j < 5 { noise } else { 0.0 };
            outer.push(if j == 0 {
                base
            } else {
                [base[0] * f, base[1] * f]
            });
        }
    }
    let blocks = vec![og.clone(), (*ni, 6, outer)];
    write_p2d(&d.join("two.dat.xy"), &blocks);
    for (direction, normalized) in [("j", false), ("i", false), ("j", true)] {
        let mut args = vec![
            "smooth",
            "two.dat.xy",
            "--direction",
            direction,
            "--iterations",
            "20",
            "--out",
            "s.xy",
        ];
        if normalized {
            args.push("--normalized");
        }
        let r = json(&d, &args);
        let got = read_p2d(&d.join("s.xy"));
        let mut moved = false;
        for (b, (before, after)) in blocks.iter().zip(&got).enumerate() {
            let (ni, nj, p0) = before;
            let p1 = &after.2;
            for j in 0..*nj {
                for i in 0..*ni {
                    let k = i + ni * j;
                    let end = if direction == "j" {
                        j == 0 || j + 1 == *nj
                    } else {
                        i == 0 || i + 1 == *ni
                    };
                    if end {
                        assert_eq!(
                            p0[k].map(f64::to_bits),
                            p1[k].map(f64::to_bits),
                            "block {b} ({i},{j}) {direction}"
                        );
                    }
                    moved |= p0[k] != p1[k];
                }
                // The seam stays closed: both copies equal, bit for bit.
                assert_eq!(
                    p1[ni * j].map(f64::to_bits),
                    p1[ni - 1 + ni * j].map(f64::to_bits)
                );
            }
        }
        assert!(moved, "{direction}: smoothing must move something");
        // The interface: block 2's first line equals block 1's last line, bit for bit.
        let (ni, nj, a) = &got[0];
        for i in 0..*ni {
            assert_eq!(
                a[i + ni * (nj - 1)].map(f64::to_bits),
                got[1].2[i].map(f64::to_bits)
            );
        }
        assert_eq!(r["flipped_cells"], 0, "{r}");
        assert!(
            r["pinned_coincident_points"].as_u64().unwrap() >= (2 * nj + ni) as u64,
            "{r}"
        );
    }
}

#[test]
fn uniform_lines_stay_uniform_and_stretching_is_reported_honestly() {
    let d = tmp_dir("smooth-uniform");
    let (ni, nj) = (17, 9);
    let pts: Vec<[f64; 2]> = (0..nj)
        .flat_map(|j| (0..ni).map(move |i| [0.25 * i as f64, 0.5 * j as f64 + 0.1 * i as f64]))
        .collect();
    write_p2d(&d.join("u.fmt.xy"), &[(ni, nj, pts.clone())]);
    for direction in ["i", "j"] {
        let r = json(
            &d,
            &[
                "smooth",
                "u.fmt.xy",
                "--direction",
                direction,
                "--iterations",
                "30",
                "--out",
                "o.xy",
            ],
        );
        let after = r["max_stretching_after"].as_f64().unwrap();
        assert!((after - 1.0).abs() < 1e-9, "{r}");
        assert!(r["max_laplacian_s_after"].as_f64().unwrap() < 1e-12, "{r}");
        let got = read_p2d(&d.join("o.xy"));
        for (a, b) in got[0].2.iter().zip(&pts) {
            assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
        }
    }
}
