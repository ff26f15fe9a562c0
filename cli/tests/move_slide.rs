//! Sliding symmetry planes (`deform move --slide`, engine level) on SU2's public half-model
//! `sphere_slice_2syms.su2` (a 9° slice of the flow around a unit sphere, far field at radius
//! 10, symmetry planes z = 0 and the plane at 9° about the x axis, which meet on the axis):
//! the wall moves 0.1 radius along the axis. Sliding nodes stay on their planes to 1e-12 of
//! the mesh size (checked against planes computed here from two far nodes, not the kernel's
//! fit) and the smallest volume ratio beats the pinned planes, for every method.

use deform_cli::engine::{
    quality, run_move, run_move_sliding, Motion, MoveInput, MoveMethod, MoveResult, MoveSolver,
    SlideMarker, Stiffness,
};
use deform_cli::formats::su2::{parse_su2, Su2Mesh};
use deform_cli::formats::CellList;
use deform_kernel::CellKind;

fn sphere() -> Su2Mesh {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/sphere_slice_2syms.su2"
    );
    parse_su2(&std::fs::read(path).unwrap()).unwrap()
}

const SYMMETRY: [&str; 2] = ["symmetry_left", "symmetry_right"];

fn markers<'a>(mesh: &'a Su2Mesh, names: &[&str]) -> Vec<&'a CellList> {
    mesh.markers
        .iter()
        .filter(|m| names.contains(&m.name.as_str()))
        .map(|m| &m.elements)
        .collect()
}

fn input(mesh: &Su2Mesh, method: MoveMethod, pinned: bool) -> MoveInput<'_> {
    let mut fixed = vec!["farfield"];
    if pinned {
        fixed.extend(SYMMETRY);
    }
    MoveInput {
        split: None,
        graph: None,
        dim: mesh.dim,
        points: &mesh.points,
        cells: &mesh.elements,
        moved: markers(mesh, &["wall"]),
        fixed: markers(mesh, &fixed),
        motion: Motion::Translate([0.1, 0.0, 0.0]),
        method,
        solver: MoveSolver::Amg,
        amg_strength: 0.0,
        tol: 1e-10,
        max_iter: 20_000,
        idw_exponent: 2.0,
        stiffness: Stiffness::Batina,
        idw_fast: None,
        reach: None,
    }
}

fn slide(mesh: &Su2Mesh) -> Vec<SlideMarker<'_>> {
    mesh.markers
        .iter()
        .filter(|m| SYMMETRY.contains(&m.name.as_str()))
        .map(|m| SlideMarker {
            name: &m.name,
            elements: &m.elements,
        })
        .collect()
}

fn min_ratio(mesh: &Su2Mesh, r: &MoveResult) -> f64 {
    quality(
        mesh.dim,
        &mesh.elements,
        &r.deformed,
        Some(&mesh.points),
        None,
    )
    .unwrap()
    .min_area_ratio
    .unwrap()
}

/// The unit normal of a marker's plane through the origin (both planes contain the x axis),
/// from the cross product of its two nodes farthest apart in angle — independent of
/// `fit_plane`.
fn plane_normal(mesh: &Su2Mesh, name: &str) -> ([f64; 3], Vec<u32>) {
    let m = mesh.marker(name).unwrap();
    let mut nodes = m.elements.nodes.clone();
    nodes.sort_unstable();
    nodes.dedup();
    let p = |i: u32| mesh.points[i as usize];
    let a = nodes
        .iter()
        .copied()
        .max_by(|&x, &y| p(x)[0].total_cmp(&p(y)[0]))
        .unwrap();
    let b = nodes
        .iter()
        .copied()
        .max_by(|&x, &y| {
            let h = |v: u32| p(v)[1].hypot(p(v)[2]);
            h(x).total_cmp(&h(y))
        })
        .unwrap();
    let (u, v) = (p(a), p(b));
    let c = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    (c.map(|x| x / l), nodes)
}

#[test]
fn sphere_slice_slides_and_beats_pinned_planes() {
    let mesh = sphere();
    let wall: Vec<u32> = {
        let mut v = markers(&mesh, &["wall", "farfield"])
            .iter()
            .flat_map(|l| l.nodes.clone())
            .collect::<Vec<_>>();
        v.sort_unstable();
        v
    };
    let size = 20.0; // the far field's diameter
    for method in [
        MoveMethod::Spring,
        MoveMethod::Quaternion,
        MoveMethod::Idw,
        MoveMethod::AngleCg,
    ] {
        let pinned = run_move(&input(&mesh, method, true)).unwrap();
        let slid = run_move_sliding(&input(&mesh, method, false), &slide(&mesh)).unwrap();
        assert!(pinned.converged && slid.converged, "{method:?}");
        assert!(slid.sliding_nodes > 2700, "{}", slid.sliding_nodes);
        let mut worst = 0.0f64;
        let mut moved = 0.0f64;
        for name in SYMMETRY {
            let (n, nodes) = plane_normal(&mesh, name);
            for &i in &nodes {
                if wall.binary_search(&i).is_ok() {
                    continue;
                }
                let x = slid.deformed[i as usize];
                let off = (n[0] * x[0] + n[1] * x[1] + n[2] * x[2]).abs();
                worst = worst.max(off);
                moved = moved.max((x[0] - mesh.points[i as usize][0]).abs());
            }
        }
        let (rp, rs) = (min_ratio(&mesh, &pinned), min_ratio(&mesh, &slid));
        eprintln!(
            "{method:?}: min volume ratio pinned {rp:.4}, sliding {rs:.4}; max off-plane {:.2e} of the size (kernel's own measure {:.2e})",
            worst / size,
            slid.max_slide_offset / size
        );
        assert!(worst <= 1e-12 * size, "{method:?}: {worst:e}");
        assert!(moved > 1e-3, "{method:?}: symmetry nodes did not slide");
        assert!(rs > rp, "{method:?}: sliding {rs} <= pinned {rp}");
    }
}

/// `--method angle-cg --slide`: the default multigrid-preconditioned CG and the node-block CG
/// (`--solver cg`) solve the same projected system, so they agree to the tolerance, and the
/// multigrid run needs fewer iterations.
#[test]
fn angle_cg_sliding_multigrid_matches_node_blocks() {
    let mesh = sphere();
    let amg = run_move_sliding(&input(&mesh, MoveMethod::AngleCg, false), &slide(&mesh)).unwrap();
    let blocks = run_move_sliding(
        &MoveInput {
            solver: MoveSolver::Cg,
            amg_strength: 0.0,
            ..input(&mesh, MoveMethod::AngleCg, false)
        },
        &slide(&mesh),
    )
    .unwrap();
    assert!(amg.converged && blocks.converged);
    let diff = amg
        .deformed
        .iter()
        .zip(&blocks.deformed)
        .flat_map(|(a, b)| (0..3).map(move |k| (a[k] - b[k]).abs()))
        .fold(0.0f64, f64::max);
    eprintln!(
        "angle-cg --slide: multigrid {} iterations, node blocks {}, max difference {diff:.1e}",
        amg.iterations, blocks.iterations
    );
    // Relative residual 1e-10 of a 0.1 translation.
    assert!(diff < 1e-7, "{diff:e}");
    assert!(amg.iterations < blocks.iterations);
}

/// A marker that is not planar is refused with a clear message, naming the marker.
#[test]
fn curved_marker_is_refused() {
    let mesh = sphere();
    let wall = mesh.marker("wall").unwrap();
    let s = [SlideMarker {
        name: "wall",
        elements: &wall.elements,
    }];
    let inp = input(&mesh, MoveMethod::Spring, false);
    let inp = MoveInput {
        split: None,
        graph: None,
        moved: markers(&mesh, &["farfield"]),
        fixed: Vec::new(),
        ..inp
    };
    let e = run_move_sliding(&inp, &s).unwrap_err().to_string();
    assert!(
        e.contains("--slide wall") && e.contains("not planar"),
        "{e}"
    );
    // A 2D "plane" is a line: a bent line is refused the same way.
    let mut pts = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.1, 0.0],
        [1.0, 1.0, 0.0],
    ];
    pts.push([0.5, 0.5, 0.0]);
    let mut cells = CellList::new();
    cells.push(CellKind::Triangle, &[0, 1, 4]);
    cells.push(CellKind::Triangle, &[1, 2, 4]);
    cells.push(CellKind::Triangle, &[2, 3, 4]);
    cells.push(CellKind::Triangle, &[3, 0, 4]);
    let mut bottom = CellList::new();
    bottom.push(CellKind::Line, &[0, 1]);
    bottom.push(CellKind::Line, &[1, 2]);
    let mut top = CellList::new();
    top.push(CellKind::Line, &[2, 3]);
    top.push(CellKind::Line, &[3, 0]);
    let inp = MoveInput {
        split: None,
        graph: None,
        dim: 2,
        points: &pts,
        cells: &cells,
        moved: vec![&top],
        fixed: Vec::new(),
        motion: Motion::Translate([0.1, 0.0, 0.0]),
        method: MoveMethod::Spring,
        solver: MoveSolver::Cg,
        amg_strength: 0.0,
        tol: 1e-10,
        max_iter: 100,
        idw_exponent: 2.0,
        stiffness: Stiffness::Batina,
        idw_fast: None,
        reach: None,
    };
    let e = run_move_sliding(
        &inp,
        &[SlideMarker {
            name: "bottom",
            elements: &bottom,
        }],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("--slide bottom") && e.contains("not straight"),
        "{e}"
    );
}

mod common;

/// Runs `deform --json ARGS` in `dir`: (exit code, stdout JSON or Null, stderr).
fn deform(dir: &std::path::Path, args: &[&str]) -> (Option<i32>, serde_json::Value, String) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(dir)
        .arg("--json")
        .args(args)
        .output()
        .expect("run deform");
    let v = serde_json::from_slice(&o.stdout).unwrap_or(serde_json::Value::Null);
    (
        o.status.code(),
        v,
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `deform move … --slide symmetry_left --slide symmetry_right` on the sphere slice: the
/// written file (read back) has every symmetry node on its original plane to 1e-12 of the
/// mesh size, the report's minimum volume ratio beats the pinned run, and misuse is refused.
#[test]
fn cli_slide_on_the_sphere_slice() {
    let dir = common::tmp_dir("move_slide");
    let mesh = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/sphere_slice_2syms.su2"
    );
    let base = [
        "move",
        mesh,
        "--marker",
        "wall",
        "--translate",
        "0.1,0,0",
        "--method",
        "spring",
    ];
    let run = |extra: &[&str], out: &str| {
        let mut args: Vec<&str> = base.to_vec();
        args.extend(extra);
        args.extend(["--out", out]);
        deform(&dir, &args)
    };
    let (code, pinned, err) = run(&[], "pinned.su2");
    assert_eq!(code, Some(0), "{err}");
    let (code, slid, err) = run(
        &["--slide", "symmetry_left", "--slide", "symmetry_right"],
        "slid.su2",
    );
    assert_eq!(code, Some(0), "{err}");
    let (rp, rs) = (
        pinned["min_volume_ratio"].as_f64().unwrap(),
        slid["min_volume_ratio"].as_f64().unwrap(),
    );
    eprintln!("deform move --method spring: min volume ratio pinned {rp:.4}, sliding {rs:.4}");
    assert!(rs > rp + 0.3, "sliding {rs}, pinned {rp}");
    assert_eq!(slid["sliding_nodes"].as_u64(), Some(2792));
    assert_eq!(slid["inverted_cells"].as_u64(), Some(0));
    // The written file, read back: symmetry nodes on their planes.
    let original = sphere();
    let written = parse_su2(&std::fs::read(dir.join("slid.su2")).unwrap()).unwrap();
    let mut worst = 0.0f64;
    for name in SYMMETRY {
        let (n, nodes) = plane_normal(&original, name);
        for &i in &nodes {
            let x = written.points[i as usize];
            worst = worst.max((n[0] * x[0] + n[1] * x[1] + n[2] * x[2]).abs());
        }
    }
    eprintln!("written file: max distance from the symmetry planes {worst:.2e} (size 20)");
    assert!(worst <= 1e-12 * 20.0, "{worst:e}");

    // Misuse: unknown marker, moved and sliding, a curved marker, Plot3D.
    let (code, _, err) = run(&["--slide", "nope"], "x.su2");
    assert_eq!(code, Some(1));
    assert!(err.contains("\"nope\" not found"), "{err}");
    let (code, _, err) = run(&["--slide", "wall"], "x.su2");
    assert_eq!(code, Some(1));
    assert!(err.contains("both --marker and --slide"), "{err}");
    let (code, _, err) = deform(
        &dir,
        &[
            "move",
            mesh,
            "--marker",
            "wall",
            "--translate",
            "0.1,0,0",
            "--method",
            "spring",
            "--slide",
            "farfield",
            "--out",
            "x.su2",
        ],
    );
    assert_eq!(code, Some(1));
    assert!(
        err.contains("--slide farfield") && err.contains("not planar"),
        "{err}"
    );
    assert!(!dir.join("x.su2").exists());
}
