//! The user's files are never destroyed: an output that is an input is refused before anything
//! is read (also through links), an interrupted run leaves no temporary file and the previous
//! output intact, and a mesh too large for the memory available is refused with "needs".

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{deform, tmp_dir};

fn naca(dir: &Path, out: &str) {
    let o = deform(
        dir,
        &[
            "mesh",
            "naca",
            "--code",
            "2412",
            "--kind",
            "inviscid",
            "--out",
            out,
            "--surface-points",
            "32",
            "--radial-points",
            "12",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn refused(dir: &Path, args: &[&str], needle: &str) {
    let o = deform(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(err.contains(needle), "expected {needle:?} in {err:?}");
}

#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let d = tmp_dir("safety-same");
    naca(&d, "m.su2");
    let before = std::fs::read(d.join("m.su2")).unwrap();
    let mv = |out: &str| {
        vec![
            "move", "m.su2", "--marker", "airfoil", "--rotate", "3", "--method", "spring", "--out",
            out,
        ]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>()
    };
    let run = |args: Vec<String>| {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(&d, &a, "refusing to overwrite an input");
    };
    run(mv("m.su2"));
    run(mv("./m.su2"));
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(d.join("m.su2"), d.join("link.su2")).unwrap();
        std::fs::hard_link(d.join("m.su2"), d.join("hard.su2")).unwrap();
        run(mv("link.su2"));
        run(mv("hard.su2"));
    }
    // The displacement file is an input too, and so is a --vtk or --plot target.
    std::fs::write(d.join("disp.txt"), "0 0.0 0.0\n").unwrap();
    refused(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--displacements",
            "disp.txt",
            "--method",
            "spring",
            "--out",
            "disp.txt",
        ],
        "refusing to overwrite an input",
    );
    let mut args = mv("out.su2");
    args.extend(["--vtk".to_string(), "m.su2".to_string()]);
    run(args);
    refused(
        &d,
        &["convert", "m.su2", "m.su2"],
        "refusing to overwrite an input",
    );
    refused(
        &d,
        &["quality", "m.su2", "--vtk", "m.su2"],
        "refusing to overwrite an input",
    );
    assert_eq!(std::fs::read(d.join("m.su2")).unwrap(), before);
    assert!(!d.join("out.su2").exists());
}

#[test]
fn an_interrupted_write_leaves_no_temporary_file_and_the_old_output() {
    let d = tmp_dir("safety-signal");
    std::fs::write(d.join("big.su2"), b"previous output\n").unwrap();
    for signal in ["TERM", "INT"] {
        // A grid big enough that writing it takes a while in a debug build; a bigger one if
        // the machine wrote it before the temporary file was seen.
        let mut running = None;
        for dims in ["120,120,60", "200,200,80", "300,300,100"] {
            std::fs::write(d.join("big.su2"), b"previous output\n").unwrap();
            let mut child = Command::new(env!("CARGO_BIN_EXE_deform"))
                .current_dir(&d)
                .args(["mesh", "block", "--dims", dims, "--out", "big.su2"])
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .expect("spawn deform");
            let t0 = Instant::now();
            let seen = loop {
                let has_temp = std::fs::read_dir(&d)
                    .unwrap()
                    .filter_map(|e| e.ok())
                    .any(|e| e.file_name().to_string_lossy().contains("deform-tmp"));
                if has_temp || t0.elapsed() > Duration::from_secs(120) {
                    break has_temp;
                }
                if child.try_wait().unwrap().is_some() {
                    break false;
                }
                std::thread::sleep(Duration::from_millis(2));
            };
            if seen {
                running = Some(child);
                break;
            }
            let _ = child.kill();
            let _ = child.wait();
        }
        let child = running.expect("every write finished before the signal could be sent");
        let status = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let out = child.wait_with_output().unwrap();
        let expected = if signal == "TERM" { 128 + 15 } else { 128 + 2 };
        assert_eq!(
            out.status.code(),
            Some(expected),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let left: Vec<String> = std::fs::read_dir(&d)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(left, vec!["big.su2".to_string()], "after SIG{signal}");
        assert_eq!(
            std::fs::read(d.join("big.su2")).unwrap(),
            b"previous output\n"
        );
    }
}

#[test]
fn a_mesh_too_large_for_the_memory_is_refused_with_what_it_needs() {
    let d = tmp_dir("safety-memory");
    naca(&d, "m.su2");
    let size = std::fs::metadata(d.join("m.su2")).unwrap().len();
    // Enough to read the file, not enough to deform it.
    let o = Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(&d)
        .env("DEFORM_MEMORY_LIMIT", (size + 1000).to_string())
        .args([
            "move", "m.su2", "--marker", "airfoil", "--rotate", "3", "--method", "spring", "--out",
            "out.su2",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("m.su2: deform move on this mesh needs about"),
        "{err}"
    );
    assert!(err.contains("GiB available"), "{err}");
    assert!(!d.join("out.su2").exists());
    // Not even enough to read it.
    let o = Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(&d)
        .env("DEFORM_MEMORY_LIMIT", "100")
        .args(["quality", "m.su2"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("reading this file needs about"), "{err}");
}

/// `deform mesh` with sizes that do not fit in the memory available is refused with what it
/// needs before anything is allocated (it aborted with a backtrace when an allocation
/// failed), and writes nothing. The limit is set low so that the unfixed tool would just
/// generate these meshes (and fail the test) instead of exhausting the machine.
#[test]
fn a_generated_mesh_too_large_for_the_memory_is_refused() {
    let d = tmp_dir("safety-mesh-memory");
    for args in [
        &["mesh", "block", "--dims", "100,100,20", "--out", "b.vts"][..],
        &[
            "mesh",
            "naca",
            "--kind",
            "viscous",
            "--surface-points",
            "400",
            "--radial-points",
            "400",
            "--out",
            "b.su2",
        ][..],
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_deform"))
            .current_dir(&d)
            .env("DEFORM_MEMORY_LIMIT", "10000000")
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains("generating this mesh needs about"), "{err}");
    }
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0);
}
