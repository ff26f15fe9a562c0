//! `deform move` on a Plot3D grid with transfinite interpolation: the --wall face moves
//! rigidly (exactly), the opposite face keeps its bits, and the interior follows. Cell
//! orientation is checked here with independent corner cross products.

mod common;

use std::path::Path;

use common::{deform, tmp_dir};
use serde_json::Value;

/// An elliptic O-grid (i around, j outward), 2D ASCII Plot3D with a block count.
fn ogrid(dir: &Path) -> (usize, usize, Vec<[f64; 2]>) {
    let (ni, nj) = (49, 17);
    let mut pts = Vec::new();
    for j in 0..nj {
        let r = 1.0 + 0.05 * (1.25f64.powi(j as i32) - 1.0) / 0.25;
        for i in 0..ni {
            let th = std::f64::consts::TAU * (i % (ni - 1)) as f64 / (ni - 1) as f64;
            pts.push([
                0.5 * r * th.cos(),
                0.12 * r * th.sin() * (1.0 + 0.3 * j as f64),
            ]);
        }
    }
    let mut s = format!("1\n{ni} {nj}\n");
    for c in 0..2 {
        let v: Vec<String> = pts.iter().map(|p| format!("{:?}", p[c])).collect();
        s.push_str(&v.join(" "));
        s.push('\n');
    }
    std::fs::write(dir.join("o.xy"), s).unwrap();
    (ni, nj, pts)
}

fn read(dir: &Path, name: &str) -> Vec<[f64; 3]> {
    let g = deform_cli::parse_plot3d(&std::fs::read(dir.join(name)).unwrap(), &Default::default())
        .unwrap()
        .0;
    g.blocks[0].points.clone()
}

#[test]
fn quaternion_tfi_moves_the_wall_rigidly_and_keeps_the_cells() {
    let d = tmp_dir("move-tfi");
    let (ni, nj, pts) = ogrid(&d);
    for method in ["tfi", "tfi-displacement"] {
        let out = format!("{method}.xy");
        let o = deform(
            &d,
            &[
                "--json", "move", "o.xy", "--method", method, "--wall", "jmin", "--rotate", "20",
                "--center", "0,0", "--out", &out,
            ],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: Value = serde_json::from_slice(&o.stdout).unwrap();
        let got = read(&d, &out);
        let (c, s) = (20f64.to_radians().cos(), 20f64.to_radians().sin());
        for i in 0..ni {
            let p = pts[i];
            let w = got[i];
            assert!(
                (w[0] - (c * p[0] - s * p[1])).abs() < 1e-12,
                "{method} wall {i}"
            );
            assert!(
                (w[1] - (s * p[0] + c * p[1])).abs() < 1e-12,
                "{method} wall {i}"
            );
            let f = (nj - 1) * ni + i;
            assert_eq!(
                [got[f][0], got[f][1]],
                pts[f],
                "{method}: the far face keeps its bits"
            );
        }
        // Independent orientation count: every quad's corner cross products.
        // The grid turns clockwise (i runs counter-clockwise, j outward): sense −1.
        let sense = -1.0;
        let mut folded = 0;
        for j in 0..nj - 1 {
            for i in 0..ni - 1 {
                let q = [
                    i + ni * j,
                    i + 1 + ni * j,
                    i + 1 + ni * (j + 1),
                    i + ni * (j + 1),
                ];
                let bad = (0..4).any(|k| {
                    let (a, n, v) = (got[q[k]], got[q[(k + 1) % 4]], got[q[(k + 3) % 4]]);
                    sense * ((n[0] - a[0]) * (v[1] - a[1]) - (n[1] - a[1]) * (v[0] - a[0])) <= 0.0
                });
                folded += usize::from(bad);
            }
        }
        assert_eq!(r["folded_cells"], folded, "{method}: {r}");
        if method == "tfi" {
            assert_eq!(folded, 0, "quaternion TFI keeps the thin wall cells: {r}");
        }
    }
}

#[test]
fn tfi_needs_a_structured_grid_and_a_wall() {
    let d = tmp_dir("move-tfi-refusals");
    ogrid(&d);
    let o = deform(
        &d,
        &[
            "move", "o.xy", "--method", "tfi", "--rotate", "5", "--out", "x.xy",
        ],
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--wall"));
    let o = deform(
        &d,
        &[
            "move", "o.xy", "--method", "spring", "--wall", "jmin", "--rotate", "5", "--out",
            "x.xy",
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = deform(
        &d,
        &[
            "mesh",
            "naca",
            "--code",
            "0012",
            "--kind",
            "ogrid",
            "--out",
            "m.su2",
            "--surface-points",
            "32",
            "--radial-points",
            "12",
            "--boundary-layers",
            "4",
            "--first-layer",
            "0.01",
        ],
    );
    assert!(o.status.success());
    let o = deform(
        &d,
        &[
            "move", "m.su2", "--marker", "airfoil", "--method", "tfi", "--rotate", "5", "--out",
            "y.su2",
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!d.join("x.xy").exists() && !d.join("y.su2").exists());
}
