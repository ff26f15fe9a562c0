//! `deform smooth --free-end` (issue 33): Alter's solution-adapted grid with a rough outer
//! boundary, smoothed along k with a free outer end in every block or in one; the default
//! fixed ends no longer refuse it; free faces on seams or interfaces are refused.

mod common;

use std::path::Path;

use common::{deform_json, deform_refused, tmp_dir};
use deform_kernel::taubin::{
    smooth_arclength, smooth_arclength_scratch_len, LineEnd, SmoothOptions,
};
use deform_kernel::{Block, Direction};
use deform_meshgen::{adapted_block, AdaptedSpec};

type P3 = [f64; 3];
type Grid = Vec<([usize; 3], Vec<P3>)>;

const DIMS: [usize; 3] = [41, 33, 49];

/// A multi-block 3D ASCII Plot3D file (block count first).
fn write_p3d(path: &Path, blocks: &Grid) {
    let mut s = format!("{}\n", blocks.len());
    for (d, _) in blocks {
        s.push_str(&format!("{} {} {}\n", d[0], d[1], d[2]));
    }
    for (_, pts) in blocks {
        for c in 0..3 {
            let v: Vec<String> = pts.iter().map(|p| format!("{:?}", p[c])).collect();
            s.push_str(&v.join(" "));
            s.push('\n');
        }
    }
    std::fs::write(path, s).unwrap();
}

/// Reads a file written by `write_p3d` or by `deform` in that layout.
fn read_p3d(path: &Path) -> Grid {
    let text = std::fs::read_to_string(path).unwrap();
    let mut it = text.split_whitespace();
    let mut next = || it.next().unwrap().to_string();
    let nb: usize = next().parse().unwrap();
    let dims: Vec<[usize; 3]> = (0..nb)
        .map(|_| [0; 3].map(|_| next().parse().unwrap()))
        .collect();
    dims.into_iter()
        .map(|d| {
            let n = d[0] * d[1] * d[2];
            let c: Vec<Vec<f64>> = (0..3)
                .map(|_| (0..n).map(|_| next().parse().unwrap()).collect())
                .collect();
            (d, (0..n).map(|p| [c[0][p], c[1][p], c[2][p]]).collect())
        })
        .collect()
}

/// The adapted block, and a copy moved 10 units along x (a second block touching nothing).
fn two_blocks() -> Grid {
    let a = adapted_block(&AdaptedSpec {
        dims: DIMS,
        ..AdaptedSpec::default()
    })
    .unwrap();
    let b = a.iter().map(|p| [p[0] + 10.0, p[1], p[2]]).collect();
    vec![(DIMS, a), (DIMS, b)]
}

/// The kernel's result for one block (k-lines, 30 iterations, the paper's λ, μ).
fn kernel(points: &[P3], last: LineEnd) -> Vec<P3> {
    let block = Block::new(DIMS).unwrap();
    let mut o = SmoothOptions::new(Direction::K);
    o.ends[1] = last;
    let mut p = points.to_vec();
    let mut s = vec![0.0; smooth_arclength_scratch_len::<3>(&block, Direction::K, None)];
    smooth_arclength(&block, &mut p, &o, &mut s).unwrap();
    p
}

fn close(a: &[P3], b: &[P3]) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (0..3).all(|c| (x[c] - y[c]).abs() <= 1e-12 * (1.0 + y[c].abs())))
}

#[test]
fn free_outer_end_per_block_and_default_fixed_ends_on_an_adapted_grid() {
    let dir = tmp_dir("smooth-free-end");
    let grid = two_blocks();
    write_p3d(&dir.join("adapted.xyz"), &grid);
    let face = DIMS[0] * DIMS[1];
    let outer = face * (DIMS[2] - 1);
    let run = |extra: &[&str], out: &str| {
        let mut args = vec!["--json", "smooth", "adapted.xyz", "--direction", "k"];
        args.extend_from_slice(&["--iterations", "30", "--out", out]);
        args.extend_from_slice(extra);
        let r = deform_json(&dir, &args);
        (r, read_p3d(&dir.join(out)))
    };

    // Every block free.
    let (r, all) = run(&["--free-end", "kmax"], "all.xyz");
    assert_eq!(
        r["free_ends"],
        serde_json::json!(["block 1: kmax", "block 2: kmax"])
    );
    assert_eq!(r["flipped_cells"], 0);
    for ((_, got), (_, input)) in all.iter().zip(&grid) {
        assert!(close(got, &kernel(input, LineEnd::Free)));
        assert_eq!(got[..face], input[..face], "wall");
        assert_ne!(got[outer..], input[outer..], "outer boundary");
    }

    // Only block 2 free: block 1 keeps its outer face bit for bit.
    let (r, one) = run(&["--free-end", "2:kmax"], "one.xyz");
    assert_eq!(r["free_ends"], serde_json::json!(["block 2: kmax"]));
    assert_eq!(one[0].1[outer..], grid[0].1[outer..]);
    assert!(close(&one[0].1, &kernel(&grid[0].1, LineEnd::Fixed)));
    assert!(close(&one[1].1, &all[1].1));

    // The default (fixed ends) no longer refuses the adapted grid.
    let (r, fixed) = run(&[], "fixed.xyz");
    assert_eq!(r["flipped_cells"], 0);
    assert_eq!(fixed[0].1[outer..], grid[0].1[outer..]);
    assert_ne!(fixed[0].1, grid[0].1);
}

#[test]
fn free_faces_that_cannot_slide_are_refused_and_nothing_is_written() {
    let dir = tmp_dir("smooth-free-end-refused");
    let mut grid = two_blocks();
    write_p3d(&dir.join("two.xyz"), &grid);
    let refused = |file: &str, extra: &[&str], needle: &str| {
        let mut args = vec!["smooth", file, "--direction", "k", "--iterations", "30"];
        args.extend_from_slice(&["--out", "out.xyz"]);
        args.extend_from_slice(extra);
        deform_refused(&dir, &args, 1, needle, "out.xyz");
    };
    refused(
        "two.xyz",
        &["--free-end", "kmin"],
        "only the face at the end",
    );
    refused(
        "two.xyz",
        &["--free-end", "jmax"],
        "only the face at the end",
    );
    refused("two.xyz", &["--free-end", "3:kmax"], "blocks 1 to 2");
    refused("two.xyz", &["--free-end", "x:kmax"], "not a block number");
    refused(
        "two.xyz",
        &["--free-end", "kmax", "--normalized"],
        "needs the physical arclength",
    );
    // Block 2's outer face touches block 1's outer face at one point: an interface.
    let dims = grid[0].0;
    let outer = dims[0] * dims[1] * (dims[2] - 1);
    grid[1].1[outer] = grid[0].1[outer + 5];
    write_p3d(&dir.join("touching.xyz"), &grid);
    refused(
        "touching.xyz",
        &["--free-end", "1:kmax"],
        "block 1: the free face kmax has point i=6, j=1, k=49 that coincides",
    );
}
