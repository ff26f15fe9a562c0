//! The C ABI seen from C and Fortran: builds `libdeform_kernel` (static and shared; crate
//! `deform-kernel-capi` in `ffi/capi`, `panic = "abort"`), compiles the C and Fortran examples and the C bad-input program against
//! both, runs them, and compares their printed bit patterns with the Rust API on the same
//! inputs. Needs `gcc`, `g++`, `gfortran` and `nm` on PATH (`cargo xtask ci` installs gfortran).

#[path = "../support/mod.rs"]
mod support;

use std::process::Command;

use support::c_build::*;

use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Quat, QuatAverage};

/// What `ffi/examples/mesh_basics.{c,f90}` must print, computed with the Rust API.
fn expected_mesh_basics() -> String {
    let mut out = String::new();
    let co = [0u32, 4, 8, 12, 16];
    let cn = [0u32, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7];
    let ck = [9u8; 4];
    let cells = Cells::new(9, &co, &cn, &ck).unwrap();
    let mut offsets = [0u32; 10];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, true)];
    let used = graph_from_cells(&cells, true, &mut offsets, &mut targets).unwrap();
    out += &format!("offsets {}\n", offsets.map(|o| o.to_string()).join(" "));
    let t: Vec<String> = targets[..used].iter().map(|t| t.to_string()).collect();
    out += &format!("targets {}\n", t.join(" "));

    let points: Vec<[f64; 3]> = (0..9)
        .map(|i| [(i % 3) as f64 * 0.5, (i / 3) as f64 * 0.25, 0.0])
        .collect();
    let q = Quat::from_axis_angle([0.0, 0.0, 1.0], 0.3).unwrap();
    let qn = q.normalize().unwrap();
    let rotated: Vec<f64> = points.iter().flat_map(|&p| qn.rotate(p)).collect();
    out += &hex64("rotated", &rotated);
    let q32 = Quat::from_axis_angle([0.0f32, 0.0, 1.0], 0.3)
        .unwrap()
        .normalize()
        .unwrap();
    let rotated32: Vec<f32> = points
        .iter()
        .flat_map(|p| q32.rotate([p[0] as f32, p[1] as f32, 0.0]))
        .collect();
    out += &hex32("rotated_f32", &rotated32);
    let plane32: Vec<f32> = points
        .iter()
        .flat_map(|p| q32.rotate_2d([p[0] as f32, p[1] as f32]))
        .collect();
    out += &hex32("rotated_2d_f32", &plane32);
    let arc = Quat::rotation_arc([1.0, 0.0, 0.0], [0.0, 1.0, 0.5]).unwrap();
    out += &hex64("arc", &arc.to_array());
    let mid = Quat::slerp(q, arc, 0.25).unwrap();
    out += &hex64("slerp", &mid.to_array());
    let mut avg = QuatAverage::new();
    avg.add(q, 1.0);
    avg.add(arc, 2.0);
    avg.add(-mid, 0.5);
    out += &hex64("average", &avg.result().unwrap().to_array());
    out
}

#[test]
fn c_example_matches_rust_bit_for_bit() {
    let src = workspace().join("ffi/examples/mesh_basics.c");
    let flags = c_flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let expected = expected_mesh_basics();
    for (link, name) in [
        (Link::Static, "mesh_basics_c_static"),
        (Link::Shared, "mesh_basics_c_shared"),
    ] {
        let exe = tmp(name);
        compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
        assert_eq!(run(&exe), expected, "{name}");
    }
}

#[test]
fn header_compiles_as_cpp() {
    let src = tmp("header_check.cpp");
    std::fs::write(
        &src,
        "#include \"deform_kernel.h\"\nint main() { return dk_status_str(DK_OK)[0] == 0; }\n",
    )
    .unwrap();
    let inc = format!("-I{}", workspace().join("ffi/generated").display());
    let exe = tmp("header_check_cpp");
    compile(
        "g++",
        &[src],
        &[
            "-std=c++11",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
            &inc,
        ],
        Link::Static,
        &exe,
    );
    assert_eq!(run(&exe), "");
}

#[test]
fn fortran_example_matches_rust_bit_for_bit() {
    let module = workspace().join("ffi/generated/deform_kernel.f90");
    let src = workspace().join("ffi/examples/mesh_basics.f90");
    let expected = expected_mesh_basics();
    for (link, name) in [
        (Link::Static, "mesh_basics_f_static"),
        (Link::Shared, "mesh_basics_f_shared"),
    ] {
        let moddir = tmp(&format!("{name}_mod"));
        std::fs::create_dir_all(&moddir).unwrap();
        let jflag = format!("-J{}", moddir.display());
        let exe = tmp(name);
        compile(
            "gfortran",
            &[module.clone(), src.clone()],
            &["-std=f2008", "-Wall", "-Werror", &jflag],
            link,
            &exe,
        );
        assert_eq!(run(&exe), expected, "{name}");
    }
}

/// The Fortran quality wrappers (`ffi/tests/quality.f90`): exact measures and Jacobians, a
/// rigid motion and a fold compared, a partial wall refused.
#[test]
fn fortran_quality_wrappers() {
    assert_eq!(fortran_test("quality"), "quality: every check held\n");
}

/// The Fortran spring and graph-Taubin wrappers and the parameter-struct constructors
/// (`ffi/tests/solvers.f90`): a fixed-end chain solved exactly, the residual through a
/// `dk_spring_system` built by `dkf_spring_system`, a NULL array in it refused, a linear field
/// kept by the λ|μ filter and a spike damped; the multigrid wrapper
/// `dkf_spring_solve_linear_amg` (and `_f32`) solving the chain, and the raw
/// `dk_spring_solve_linear_amg` refusing pools one element short with the values untouched;
/// `dk_spring_solve_linear_sliding` (and `_f32`) with a `dk_constraints` built by
/// `dkf_constraints`, a node sliding along the chain, and directions one short refused.
#[test]
fn fortran_solver_wrappers_and_structs() {
    assert_eq!(fortran_test("solvers"), "solvers: every check held\n");
}

#[test]
fn bad_input_from_c_returns_documented_status_and_writes_nothing() {
    let src = workspace().join("ffi/tests/bad_input.c");
    let flags = c_flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let exe = tmp("bad_input_c");
    compile("gcc", &[src], &flags, Link::Static, &exe);
    assert_eq!(run(&exe), "bad_input: every check held\n");
}

/// The `dk_` symbols binutils' `nm` lists (defined, global) with `args` in `file`, sorted.
fn dk_symbols(args: &[&str], file: &std::path::Path) -> Vec<String> {
    let out = Command::new("nm")
        .args(args)
        .arg(file)
        .output()
        .expect("nm");
    assert!(out.status.success());
    let mut symbols: Vec<String> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().nth(2))
        .filter(|s| s.starts_with("dk_"))
        .map(str::to_string)
        .collect();
    symbols.sort();
    symbols
}

/// Both libraries export exactly `ffi/generated/symbols.txt`; for the static one this also shows that
/// binutils sees its symbols (an archive of embedded LLVM bitcode shows none).
#[test]
fn exported_symbols_match_the_checked_in_list() {
    let listed = std::fs::read_to_string(workspace().join("ffi/generated/symbols.txt")).unwrap();
    let listed: Vec<&str> = listed
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect();
    let so = library_dir().join("libdeform_kernel.so");
    assert_eq!(
        dk_symbols(&["-D", "--defined-only"], &so),
        listed,
        "the exported dk_ symbols changed: update ffi/generated/symbols.txt deliberately"
    );
    let a = library_dir().join("libdeform_kernel.a");
    assert_eq!(
        dk_symbols(&["-g", "--defined-only"], &a),
        listed,
        "nm does not list the static library's dk_ symbols as ffi/generated/symbols.txt has them"
    );
}

#[test]
fn quaternion_twins_from_c_hold_their_identities() {
    let src = workspace().join("ffi/tests/quaternions.c");
    let flags = c_flags();
    let mut flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let tests_dir = format!("-I{}", workspace().join("ffi/tests").display());
    flags.push(&tests_dir);
    for (link, name) in [
        (Link::Static, "quaternions_c_static"),
        (Link::Shared, "quaternions_c_shared"),
    ] {
        let exe = tmp(name);
        compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
        assert_eq!(run(&exe), "quaternions: every check held\n", "{name}");
    }
}

/// Issue #6: every exported `dk_` function is called from C. A function counts as called when
/// a C file under `ffi/tests/` or `ffi/examples/` names it, or, for an `_f32` twin, calls its
/// double name through the precision macros `SFX(name)` / `FN(name)` of the files that include
/// themselves once per precision.
#[test]
fn every_exported_function_is_called_from_c() {
    let mut c_text = String::new();
    for dir in ["ffi/tests", "ffi/examples"] {
        for entry in std::fs::read_dir(workspace().join(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "c") {
                c_text += &std::fs::read_to_string(&path).unwrap();
            }
        }
    }
    let is_word_char = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let names_word = |word: &str| {
        c_text.match_indices(word).any(|(i, _)| {
            let before = c_text[..i].chars().next_back();
            let after = c_text[i + word.len()..].chars().next();
            !before.is_some_and(is_word_char) && !after.is_some_and(is_word_char)
        })
    };
    let listed = std::fs::read_to_string(workspace().join("ffi/generated/symbols.txt")).unwrap();
    let missing: Vec<&str> = listed
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .filter(|s| {
            let via_macro = s.strip_suffix("_f32").is_some_and(|base| {
                c_text.contains(&format!("SFX({base})")) || c_text.contains(&format!("FN({base})"))
            });
            !names_word(s) && !via_macro
        })
        .collect();
    assert!(
        missing.is_empty(),
        "not called from any C program: {missing:?}"
    );
}

/// The structs of the C header: `(name, field names)`, in header order.
fn header_structs() -> Vec<(String, Vec<String>)> {
    let header =
        std::fs::read_to_string(workspace().join("ffi/generated/deform_kernel.h")).unwrap();
    let mut structs = Vec::new();
    let mut fields: Option<Vec<String>> = None;
    for line in header.lines().map(str::trim) {
        if line == "typedef struct {" {
            fields = Some(Vec::new());
        } else if let Some(f) = fields.as_mut().filter(|_| !line.starts_with("//")) {
            if let Some(name) = line.strip_prefix("} ") {
                let name = name.trim_end_matches(';').to_string();
                structs.push((name, fields.take().unwrap()));
            } else if let Some(decl) = line.strip_suffix(';') {
                let field = decl.rsplit([' ', '*']).next().unwrap();
                f.push(field.split('[').next().unwrap().to_string());
            }
        }
    }
    structs
}

/// The Fortran `bind(C)` types (generated from the header by `cargo xtask codegen`) have the
/// C structs' layout as gfortran and gcc see it: every size and field offset, printed by a C
/// program (`sizeof`, `offsetof`) and a Fortran one (`c_sizeof`, `c_loc` differences).
#[test]
fn fortran_types_have_the_c_layouts() {
    let structs = header_structs();
    assert!(
        structs.len() >= 20,
        "{} structs in the header",
        structs.len()
    );
    let mut c = String::from(
        "#include <stddef.h>\n#include <stdio.h>\n#include \"deform_kernel.h\"\nint main(void) {\n",
    );
    let mut f = String::from(
        "program layouts\n  use, intrinsic :: iso_c_binding\n  use deform_kernel\n  implicit none\n",
    );
    let mut body = String::new();
    for (k, (name, fields)) in structs.iter().enumerate() {
        c += &format!("    printf(\"{name} %zu\\n\", sizeof({name}));\n");
        f += &format!("  type({name}), target :: v{k}\n");
        body += &format!("  print '(a,1x,i0)', '{name}', c_sizeof(v{k})\n");
        for field in fields {
            c += &format!("    printf(\"{name}.{field} %zu\\n\", offsetof({name}, {field}));\n");
            body += &format!(
                "  print '(a,1x,i0)', '{name}.{field}', at(c_loc(v{k}%{field})) - at(c_loc(v{k}))\n"
            );
        }
    }
    c += "    return 0;\n}\n";
    f += &body;
    f += "contains\n  integer(c_intptr_t) function at(p)\n    type(c_ptr), intent(in) :: p\n";
    f += "    at = transfer(p, 0_c_intptr_t)\n  end function\nend program\n";
    let (c_src, f_src) = (tmp("layouts.c"), tmp("layouts.f90"));
    std::fs::write(&c_src, c).unwrap();
    std::fs::write(&f_src, f).unwrap();
    let flags = c_flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let c_exe = tmp("layouts_c");
    compile("gcc", &[c_src], &flags, Link::Static, &c_exe);
    let moddir = tmp("layouts_f_mod");
    std::fs::create_dir_all(&moddir).unwrap();
    let jflag = format!("-J{}", moddir.display());
    let f_exe = tmp("layouts_f");
    let module = workspace().join("ffi/generated/deform_kernel.f90");
    compile(
        "gfortran",
        &[module, f_src],
        &["-std=f2008", &jflag],
        Link::Static,
        &f_exe,
    );
    let (from_c, from_f) = (run(&c_exe), run(&f_exe));
    assert!(from_c.lines().count() > 100, "{from_c}");
    assert_eq!(from_f, from_c);
}
