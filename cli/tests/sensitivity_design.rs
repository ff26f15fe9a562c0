//! `deform adjoint --config`: dJ/dα of an SU2 config's design variables (SU2_DOT's job)
//! against central differences of the whole chain, `deform su2 --method spring` at DV_VALUE
//! = ±h (the surface moved by the design variables, the volume by Batina's springs) and
//! `J = ⟨w, x⟩` for a fixed random `w`: TRANSLATION, ROTATION and Hicks–Henne bumps on a
//! NACA 0012 mesh and FFD
//! variables on SU2's supersonic wedge case (its mesh file carries the FFD box). The maps are
//! linear in α (the rotation to O(h²)), so the difference equals the gradient up to rounding
//! and solver tolerance.
//! The gradient file has SU2_DOT's `of_grad.dat` form.

mod common;

use std::fmt::Write as _;
use std::path::Path;

use common::{deform_json, deform_refused, naca_mesh, read_csv, read_su2, tmp_dir, Rng};

/// A random sensitivity per node in plain rows; returns it.
fn sensitivity(dir: &Path, n: usize, dim: usize) -> Vec<[f64; 3]> {
    let mut rng = Rng(17);
    let w: Vec<[f64; 3]> = (0..n)
        .map(|_| {
            let mut v = [rng.real(), rng.real(), rng.real()];
            v[2] *= (dim == 3) as u8 as f64;
            v
        })
        .collect();
    let mut text = String::from("% node dJ/dx dJ/dy [dJ/dz]\n");
    for (i, v) in w.iter().enumerate() {
        match dim {
            3 => writeln!(text, "{i} {:e} {:e} {:e}", v[0], v[1], v[2]).unwrap(),
            _ => writeln!(text, "{i} {:e} {:e}", v[0], v[1]).unwrap(),
        }
    }
    std::fs::write(dir.join("w.txt"), text).unwrap();
    w
}

/// `J = ⟨w, x⟩` of a mesh file.
fn objective(path: &Path, w: &[[f64; 3]]) -> f64 {
    let m = read_su2(path);
    (m.points.iter().zip(w))
        .map(|(p, w)| p[0] * w[0] + p[1] * w[1] + p[2] * w[2])
        .sum()
}

/// `of_grad.dat`'s values after its `OBJECTIVE gradient ` line.
fn grad_file(path: &Path, objective: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(format!("{objective} gradient ").as_str())
    );
    lines.map(|l| l.parse().unwrap()).collect()
}

/// The gradient of the config `cfg(values)` against central differences at `h` of
/// `deform su2 --method spring`.
fn chain(dir: &Path, cfg: &dyn Fn(&[f64]) -> String, count: usize, objective_name: &str) {
    chain_with(
        dir,
        cfg,
        (count, objective_name),
        (&[], &["--method", "spring"]),
    );
}

/// [`chain`] with `adjoint` options for `deform adjoint` and `su2` for `deform su2` (the same
/// deformation); returns the gradient.
fn chain_with(
    dir: &Path,
    cfg: &dyn Fn(&[f64]) -> String,
    (count, objective_name): (usize, &str),
    (adjoint, su2): (&[&str], &[&str]),
) -> Vec<f64> {
    let (mesh, h) = ("m.su2", 1e-4);
    let m = read_su2(&dir.join(mesh));
    let w = sensitivity(dir, m.points.len(), m.dim);
    std::fs::write(dir.join("grad.cfg"), cfg(&vec![0.0; count])).unwrap();
    let r = deform_json(
        dir,
        &[
            "--json",
            "adjoint",
            mesh,
            "--sensitivity",
            "w.txt",
            "--out",
            "s.csv",
            "--config",
            "grad.cfg",
            "--grad-out",
            "of_grad.dat",
            "--tol",
            "1e-14",
        ]
        .iter()
        .chain(adjoint)
        .copied()
        .collect::<Vec<_>>(),
    );
    let grad: Vec<f64> = (r["gradient"].as_array().unwrap().iter())
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(grad.len(), count);
    assert_eq!(
        grad_file(&dir.join("of_grad.dat"), objective_name),
        grad,
        "17 digits"
    );
    let scale = grad.iter().fold(0.0f64, |s, g| s.max(g.abs()));
    assert!(scale > 1e-3, "a test that cannot fail: {grad:?}");
    for (k, &g) in grad.iter().enumerate() {
        let mut j = [0.0; 2];
        for (s, sign) in j.iter_mut().zip([1.0, -1.0]) {
            let mut values = vec![0.0; count];
            values[k] = sign * h;
            std::fs::write(dir.join("fd.cfg"), cfg(&values)).unwrap();
            let args = ["--json", "su2", "fd.cfg"].iter().chain(su2).copied();
            deform_json(dir, &args.collect::<Vec<_>>());
            *s = objective(&dir.join("out.su2"), &w);
        }
        let fd = (j[0] - j[1]) / (2.0 * h);
        let err = (fd - g).abs() / scale;
        println!("{mesh} variable {k}: adjoint {g:.10e}, central difference {fd:.10e}, relative {err:.1e}");
        assert!(err < 1e-6, "variable {k}: adjoint {g}, difference {fd}");
    }
    grad
}

/// DV_VALUE as SU2 lists it.
fn values(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[test]
fn surface_variables_gradient_is_the_central_difference_of_deform_su2() {
    let d = tmp_dir("sensitivity-design-hh");
    naca_mesh(&d, "inviscid", 64, 14, "m.su2");
    let cfg = |v: &[f64]| {
        format!(
            "MESH_FILENAME= m.su2\nMESH_OUT_FILENAME= out.su2\nMARKER_EULER= ( airfoil )\n\
             MARKER_FAR= ( farfield )\nDV_MARKER= ( airfoil )\n\
             DV_KIND= TRANSLATION, ROTATION, HICKS_HENNE, HICKS_HENNE, HICKS_HENNE\n\
             DV_PARAM= ( 0.3, -0.8, 0 ); ( 0.25, 0.1, 0, 0.25, 0.1, 1 ); ( 1, 0.5 ); ( 0, 0.3 ); ( 1, 0.1 )\n\
             DV_VALUE= {}\n\
             OPT_RELAX_FACTOR= 2\nOUTPUT_PRECISION= 17\n\
             DEFORM_STIFFNESS_TYPE= CONSTANT_STIFFNESS\nDEFORM_LINEAR_SOLVER_ERROR= 1E-14\n",
            values(v)
        )
    };
    chain(&d, &cfg, 5, "DRAG");
}

#[test]
fn ffd_gradient_is_the_central_difference_of_deform_su2() {
    let d = tmp_dir("sensitivity-design-ffd");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    std::fs::copy(data.join("wedge_inv_periodic_ffd.su2"), d.join("m.su2")).unwrap();
    let base = std::fs::read_to_string(data.join("su2_def/inv_wedge_ROE.cfg")).unwrap();
    let cfg = |v: &[f64]| {
        let kept: Vec<&str> = (base.lines())
            .filter(|l| {
                !["DV_", "MESH_", "DEFORM_STIFF"]
                    .iter()
                    .any(|k| l.starts_with(k))
            })
            .collect();
        format!(
            "{}\nMESH_FILENAME= m.su2\nMESH_OUT_FILENAME= out.su2\nDV_MARKER= ( lower )\n\
             DV_KIND= FFD_CONTROL_POINT_2D, FFD_CONTROL_POINT_2D, FFD_CAMBER_2D, FFD_THICKNESS_2D\n\
             DV_PARAM= ( MAIN_BOX, 3, 0, 0.0, 1.0 ); ( MAIN_BOX, 5, 0, 0.4, 1.0 ); ( MAIN_BOX, 4 ); ( MAIN_BOX, 6 )\n\
             DV_VALUE= {}\nOUTPUT_PRECISION= 17\n\
             DEFORM_STIFFNESS_TYPE= CONSTANT_STIFFNESS\n",
            kept.join("\n"),
            values(v)
        )
    };
    chain(&d, &cfg, 4, "SURFACE_TOTAL_PRESSURE");
}

/// The wedge's FFD config with `planes` as MARKER_DEFORM_MESH_SYM_PLANE.
fn wedge_cfg(d: &Path, planes: &'static str) -> impl Fn(&[f64]) -> String {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    std::fs::copy(data.join("wedge_inv_periodic_ffd.su2"), d.join("m.su2")).unwrap();
    let base = std::fs::read_to_string(data.join("su2_def/inv_wedge_ROE.cfg")).unwrap();
    move |v: &[f64]| {
        let kept: Vec<&str> = (base.lines())
            .filter(|l| {
                !["DV_", "MESH_", "DEFORM_STIFF", "DEFORM_LINEAR_SOLVER_ITER"]
                    .iter()
                    .any(|k| l.starts_with(k))
            })
            .collect();
        format!(
            "{}\nMESH_FILENAME= m.su2\nMESH_OUT_FILENAME= out.su2\nDV_MARKER= ( lower )\n\
             DV_KIND= FFD_CONTROL_POINT_2D, FFD_CAMBER_2D\n\
             DV_PARAM= ( MAIN_BOX, 3, 0, 0.0, 1.0 ); ( MAIN_BOX, 4 )\n\
             DV_VALUE= {}\nOUTPUT_PRECISION= 17\nDEFORM_LINEAR_SOLVER_ITER= 10000\n\
             DEFORM_STIFFNESS_TYPE= CONSTANT_STIFFNESS\n{planes}",
            kept.join("\n"),
            values(v)
        )
    }
}

/// MARKER_DEFORM_MESH_SYM_PLANE: the outlet and upper markers of the wedge slide (their
/// corner node, on both lines, is held) in `deform su2` and in the adjoint; the gradient of
/// the springs and of SU2_DEF's elasticity equals central differences of `deform su2`, and
/// differs from the gradient with the planes held fixed.
#[test]
fn symmetry_plane_gradient_is_the_central_difference_of_deform_su2() {
    let planes = "MARKER_DEFORM_MESH_SYM_PLANE= ( upper, outlet )\n";
    let runs: [(&str, &[&str], &[&str]); 2] = [
        ("spring", &[], &["--method", "spring"]),
        (
            "elasticity",
            &["--method", "elasticity", "--stiffness", "constant"],
            &["--method", "elasticity"],
        ),
    ];
    for (name, adjoint, su2) in runs {
        let d = tmp_dir(&format!("sensitivity-design-sym-{name}"));
        let cfg = wedge_cfg(&d, planes);
        let objective = "SURFACE_TOTAL_PRESSURE";
        let sliding = chain_with(&d, &cfg, (2, objective), (adjoint, su2));
        let d = tmp_dir(&format!("sensitivity-design-held-{name}"));
        let cfg = wedge_cfg(&d, "");
        let held = chain_with(&d, &cfg, (2, objective), (adjoint, su2));
        let differ = (sliding.iter().zip(&held)).any(|(a, b)| (a - b).abs() > 1e-6 * a.abs());
        assert!(differ, "{name}: sliding {sliding:?} = held {held:?}");
    }
}

/// 3D: SU2's sphere slice (two symmetry planes meeting on the axis, whose nodes slide on the
/// line) with the wall translated obliquely: dJ/dα of the springs and of SU2_DEF's elasticity equals
/// central differences of `deform su2`.
#[test]
fn symmetry_planes_in_3d_gradient_is_the_central_difference_of_deform_su2() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let runs: [(&str, &[&str], &[&str]); 2] = [
        ("spring", &[], &["--method", "spring"]),
        (
            "elasticity",
            &["--method", "elasticity", "--stiffness", "constant"],
            &["--method", "elasticity"],
        ),
    ];
    for (name, adjoint, su2) in runs {
        let d = tmp_dir(&format!("sensitivity-design-sphere-{name}"));
        std::fs::copy(data.join("sphere_slice_2syms.su2"), d.join("m.su2")).unwrap();
        let cfg = |v: &[f64]| {
            format!(
                "MESH_FILENAME= m.su2\nMESH_OUT_FILENAME= out.su2\nMARKER_FAR= ( farfield )\n\
                 MARKER_DEFORM_MESH_SYM_PLANE= ( symmetry_left, symmetry_right )\n\
                 DV_MARKER= ( wall )\nDV_KIND= TRANSLATION\n\
                 DV_PARAM= ( 0.2, 0.3, -0.1 )\nDV_VALUE= {}\n\
                 OUTPUT_PRECISION= 17\nDEFORM_STIFFNESS_TYPE= CONSTANT_STIFFNESS\n\
                 DEFORM_LINEAR_SOLVER_ERROR= 1E-14\n",
                values(v)
            )
        };
        chain_with(&d, &cfg, (1, "DRAG"), (adjoint, su2));
    }
}

/// `deform tangent --slide` and `deform adjoint --slide` on the wedge (upper and outlet
/// sliding): the dot-product identity through the files, the tangent of the sliding nodes along
/// their lines (upper: `dy = 0`; outlet: `dx = 0`), and the boundary rows without them.
#[test]
fn slide_tangent_and_adjoint_files_satisfy_the_dot_product_identity() {
    for method in [
        &["--method", "spring"][..],
        &["--method", "elasticity", "--stiffness", "constant"],
    ] {
        let d = tmp_dir(&format!("sensitivity-slide-{}", method[1]));
        let _copied = wedge_cfg(&d, "");
        let m = read_su2(&d.join("m.su2"));
        let n = m.points.len();
        let w = sensitivity(&d, n, 2);
        let nodes = |name: &str| m.marker(name).unwrap().elements.nodes.clone();
        let (upper, outlet) = (nodes("upper"), nodes("outlet"));
        let mut fixed: Vec<u32> = [nodes("inlet"), nodes("lower")].concat();
        fixed.sort_unstable();
        fixed.dedup();
        let mut rng = Rng(5);
        let mut v = vec![[0.0; 2]; n];
        let mut text = String::from("% node dx dy\n");
        for &i in &fixed {
            v[i as usize] = [rng.real(), rng.real()];
            writeln!(text, "{i} {:e} {:e}", v[i as usize][0], v[i as usize][1]).unwrap();
        }
        std::fs::write(d.join("v.txt"), text).unwrap();
        let slide = ["--slide", "upper", "--slide", "outlet", "--tol", "1e-14"];
        let run = |head: &[&str]| {
            let args: Vec<&str> = head.iter().chain(&slide).chain(method).copied().collect();
            deform_json(&d, &args);
        };
        run(&[
            "--json",
            "tangent",
            "m.su2",
            "--perturbation",
            "v.txt",
            "--out",
            "t.csv",
        ]);
        run(&[
            "--json",
            "adjoint",
            "m.su2",
            "--sensitivity",
            "w.txt",
            "--out",
            "g.csv",
        ]);
        let (jv, g) = (read_csv(&d.join("t.csv")), read_csv(&d.join("g.csv")));
        let lhs: f64 = (jv.iter())
            .map(|(i, x)| x[0] * w[*i][0] + x[1] * w[*i][1])
            .sum();
        let rhs: f64 = (g.iter())
            .map(|(i, x)| x[2] * v[*i][0] + x[3] * v[*i][1])
            .sum();
        assert!(
            (lhs - rhs).abs() <= 1e-10 * lhs.abs(),
            "{method:?}: {lhs} vs {rhs}"
        );
        let scale = jv
            .iter()
            .flat_map(|(_, x)| x.iter())
            .fold(0.0f64, |a, x| a.max(x.abs()));
        let on =
            |list: &[u32], i: usize| list.contains(&(i as u32)) && !fixed.contains(&(i as u32));
        let moved = (jv.iter()).filter(|(i, x)| on(&upper, *i) && x[0].abs() > 1e-3 * scale);
        assert!(
            moved.count() > 10,
            "{method:?}: the upper nodes do not slide"
        );
        for (i, x) in &jv {
            if on(&upper, *i) {
                assert!(x[1].abs() <= 1e-14 * scale, "upper node {i}: {x:?}");
            }
            if on(&outlet, *i) {
                assert!(x[0].abs() <= 1e-14 * scale, "outlet node {i}: {x:?}");
            }
        }
        // The adjoint's rows: the fixed markers' nodes and the held corner, no sliding node.
        assert!(g.iter().all(|(i, _)| {
            let i = *i as u32;
            fixed.contains(&i) || (upper.contains(&i) && outlet.contains(&i))
        }));
    }
}

#[test]
fn symmetry_planes_are_refused_for_methods_without_their_derivative() {
    let d = tmp_dir("sensitivity-design-sym-refused");
    let cfg = wedge_cfg(&d, "MARKER_DEFORM_MESH_SYM_PLANE= ( upper )\n");
    std::fs::write(d.join("c.cfg"), cfg(&[0.0, 0.0])).unwrap();
    let m = read_su2(&d.join("m.su2"));
    sensitivity(&d, m.points.len(), 2);
    let args = [
        "adjoint",
        "m.su2",
        "--sensitivity",
        "w.txt",
        "--out",
        "s.csv",
        "--config",
        "c.cfg",
        "--grad-out",
        "g.dat",
        "--method",
        "idw-displacements",
    ];
    deform_refused(&d, &args, 3, "sliding markers", "s.csv");
    assert!(!d.join("g.dat").exists());
}

#[test]
fn unsupported_design_variables_are_refused_with_nothing_written() {
    let d = tmp_dir("sensitivity-design-refused");
    naca_mesh(&d, "inviscid", 32, 8, "m.su2");
    let m = read_su2(&d.join("m.su2"));
    sensitivity(&d, m.points.len(), 2);
    let args = [
        "adjoint",
        "m.su2",
        "--sensitivity",
        "w.txt",
        "--out",
        "s.csv",
        "--config",
        "c.cfg",
        "--grad-out",
        "g.dat",
    ];
    let cfg = "MESH_FILENAME= m.su2\nDV_MARKER= ( airfoil )\nDV_KIND= SCALE\n\
               DV_PARAM= ( )\nDV_VALUE= 1.1\n";
    std::fs::write(d.join("c.cfg"), cfg).unwrap();
    deform_refused(&d, &args, 1, "SCALE", "s.csv");
    assert!(!d.join("g.dat").exists());
}
