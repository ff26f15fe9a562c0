//! Plot3D text as Fortran writes it (list-directed: `2*0.5` repeat counts, commas, `/`, values
//! split over lines anywhere), on NASA's CFL3D test grids (cli/tests/data/README.md) and on
//! small files written here. The reference is Fortran itself: a gfortran program reads each
//! file with `READ (u, *)` as CFL3D does and writes what it read as a raw binary stream, which
//! must equal, byte for byte, what `deform convert` writes as binary. Needs `gfortran` on PATH
//! (`cargo xtask ci` installs it).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{deform, deform_json, deform_ok, tmp_dir};
use serde_json::Value;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Reads a Plot3D text grid with list-directed input, one READ for the block count, one for
/// all dimensions and one per block (CFL3D's reader), and writes the values read, unchanged, as
/// a stream of native integers and doubles: the layout of a binary Plot3D file without record
/// markers.
const FORTRAN_READER: &str = r#"
program p3d
  implicit none
  character(len=4096) :: fin, fout, arg
  integer :: multi, dim, iblank, nb, n, np, u, o
  integer, allocatable :: id(:), jd(:), kd(:), ib(:)
  double precision, allocatable :: x(:), y(:), z(:)
  call get_command_argument(1, fin)
  call get_command_argument(2, fout)
  call get_command_argument(3, arg); read(arg, *) multi
  call get_command_argument(4, arg); read(arg, *) dim
  call get_command_argument(5, arg); read(arg, *) iblank
  open(newunit=u, file=fin, status='old', form='formatted', action='read')
  open(newunit=o, file=fout, access='stream', form='unformatted', status='replace')
  nb = 1
  if (multi == 1) then
    read(u, *) nb
    write(o) nb
  end if
  allocate(id(nb), jd(nb), kd(nb))
  kd = 1
  if (dim == 3) then
    read(u, *) (id(n), jd(n), kd(n), n = 1, nb)
    write(o) (id(n), jd(n), kd(n), n = 1, nb)
  else
    read(u, *) (id(n), jd(n), n = 1, nb)
    write(o) (id(n), jd(n), n = 1, nb)
  end if
  do n = 1, nb
    np = id(n) * jd(n) * kd(n)
    allocate(x(np), y(np), z(np), ib(np))
    if (dim == 3 .and. iblank == 1) then
      read(u, *) x, y, z, ib
      write(o) x, y, z, ib
    else if (dim == 3) then
      read(u, *) x, y, z
      write(o) x, y, z
    else if (iblank == 1) then
      read(u, *) x, y, ib
      write(o) x, y, ib
    else
      read(u, *) x, y
      write(o) x, y
    end if
    deallocate(x, y, z, ib)
  end do
end program
"#;

/// Compiles [`FORTRAN_READER`] in `dir`.
fn fortran_reader(dir: &Path) -> PathBuf {
    let src = dir.join("p3d.f90");
    let exe = dir.join("p3d");
    std::fs::write(&src, FORTRAN_READER).unwrap();
    let o = Command::new("gfortran")
        .arg(&src)
        .arg("-o")
        .arg(&exe)
        .output()
        .expect("gfortran on PATH (cargo xtask ci installs it)");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    exe
}

/// What gfortran reads from `file`, as a binary stream.
fn fortran_read(
    exe: &Path,
    file: &Path,
    out: &Path,
    multi: bool,
    dim: usize,
    iblank: bool,
) -> Vec<u8> {
    let flag = |b: bool| if b { "1" } else { "0" };
    let o = Command::new(exe)
        .arg(file)
        .arg(out)
        .args([flag(multi), &dim.to_string(), flag(iblank)])
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{}: {}",
        file.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::read(out).unwrap()
}

/// `deform convert` to a little-endian f64 binary file without record markers (the layout of
/// the Fortran stream on this machine): its bytes.
fn deform_binary(dir: &Path, input: &Path, out: &str) -> Vec<u8> {
    let input = input.to_str().unwrap();
    let args = [
        "convert",
        input,
        out,
        "--out-encoding",
        "binary",
        "--out-precision",
        "f64",
        "--out-endian",
        "little",
        "--out-records",
        "no",
    ];
    deform_ok(dir, &args);
    std::fs::read(dir.join(out)).unwrap()
}

fn json(dir: &Path, args: &[&str]) -> Value {
    deform_json(dir, &[&["--json"][..], args].concat())
}

/// The committed CFL3D grids: (file, multi-block header, blocks, points).
const CFL3D: &[(&str, bool, usize, usize)] = &[
    ("cfl3d_ramp_embed.fmt", true, 6, 14_956),
    ("cfl3d_ramp_noembed.fmt", true, 1, 6_570),
    ("cfl3d_grdflat5_skew45.fmt", false, 1, 12_610),
    ("cfl3d_grdflat5.fmt", false, 1, 12_610),
    ("cfl3d_transdiff.fmt", true, 1, 8_586),
    ("cfl3d_cyl_129x81.fmt", true, 1, 20_898),
    ("cfl3d_nozzle.p3dfmt", true, 3, 31_386),
];

/// Every CFL3D grid reads to exactly what Fortran reads; its text output reads back (by us and
/// by Fortran) to the same bits.
#[test]
fn cfl3d_text_grids_read_as_fortran_reads_them_and_round_trip_exactly() {
    let d = tmp_dir("p3d-fortran-cfl3d");
    let exe = fortran_reader(&d);
    for &(name, multi, blocks, points) in CFL3D {
        let file = data(name);
        let reference = fortran_read(&exe, &file, &d.join("ref.bin"), multi, 3, false);
        let ours = deform_binary(&d, &file, "ours.x");
        assert!(
            ours == reference,
            "{name}: deform and gfortran read different values"
        );
        let q = json(&d, &["convert", file.to_str().unwrap(), "text.fmt"]);
        assert_eq!(q["blocks"], blocks, "{name}: {q}");
        assert_eq!(q["points"], points, "{name}: {q}");
        let again = fortran_read(
            &exe,
            &d.join("text.fmt"),
            &d.join("ref2.bin"),
            multi,
            3,
            false,
        );
        assert!(
            again == reference,
            "{name}: Fortran reads our text output differently"
        );
        let back = deform_binary(&d, &d.join("text.fmt"), "back.x");
        assert!(back == reference, "{name}: text round trip changed values");
        // Binary back to text and to binary again: the same bytes.
        json(
            &d,
            &["convert", "ours.x", "text2.fmt", "--out-encoding", "ascii"],
        );
        let text1 = std::fs::read(d.join("text.fmt")).unwrap();
        assert!(
            std::fs::read(d.join("text2.fmt")).unwrap() == text1,
            "{name}"
        );
    }
}

/// A 2D multi-block grid with iblank, written in every list-directed way: repeat counts in the
/// dimensions, coordinates and iblank; commas with and without blanks; a `/` ending a record
/// after the last value of a READ (the rest of its line is a comment); values split over lines
/// at any point; `D` exponents and an exponent without its letter (`1.5-1`).
const FREE_2D_IBLANK: &str = "2 / two blocks
 3,2, 2
 2
0.0, 0.5,1.0D0 0.0 0.5
1.0 3*0.0, 3*1.5d0
 6*1 / iblank of block 1: this READ is done
 -1.,1.5-1
 2*2.0 1.0
 3.,4., 5.5
  2 * 0 , -2 1
";

#[test]
fn free_form_2d_multi_block_iblank_reads_as_fortran_reads_it() {
    let d = tmp_dir("p3d-fortran-free");
    let exe = fortran_reader(&d);
    let file = d.join("free.fmt");
    // `2 * 0` is not a repeat count in Fortran (blanks separate `2`, `*` and `0`): fix it up
    // to the form Fortran reads, and keep the malformed one for the refusal test below.
    std::fs::write(&file, FREE_2D_IBLANK.replace("2 * 0 ", "2*0 ")).unwrap();
    let reference = fortran_read(&exe, &file, &d.join("ref.bin"), true, 2, true);
    let ours = deform_binary(&d, &file, "ours.x");
    assert!(
        ours == reference,
        "deform and gfortran read different values"
    );
    let q = json(&d, &["convert", file.to_str().unwrap(), "text.fmt"]);
    assert_eq!(
        (q["blocks"].clone(), q["points"].clone()),
        (2.into(), 10.into()),
        "{q}"
    );
    assert!(
        q["input_format"]
            .as_str()
            .unwrap()
            .contains("2D ASCII, multi-block header, iblank"),
        "{q}"
    );
    let again = fortran_read(
        &exe,
        &d.join("text.fmt"),
        &d.join("ref2.bin"),
        true,
        2,
        true,
    );
    assert!(
        again == reference,
        "Fortran reads our text output differently"
    );
}

/// Null values (Fortran leaves the variable unchanged) and malformed tokens are refused with
/// the line and the token.
#[test]
fn nulls_and_bad_tokens_are_refused_with_line_and_token() {
    let d = tmp_dir("p3d-fortran-bad");
    let fixed = FREE_2D_IBLANK.replace("2 * 0 ", "2*0 ");
    let cases: &[(String, &str, &str)] = &[
        (
            fixed.replace("0.0, 0.5,1.0D0", "0.0,, 1.0D0"),
            "line 4",
            "\",\"",
        ),
        (fixed.replace("3*0.0,", "3*,"), "line 5", "\"3*\""),
        (fixed.replace("2*2.0", "2*2.0x"), "line 8", "\"2*2.0x\""),
        (fixed.replace("6*1", "0*1"), "line 6", "\"0*1\""),
        (FREE_2D_IBLANK.to_string(), "line 10", "\"*\""),
        (fixed.replace("3.,4.", "3.,NaN"), "line 9", "\"NaN\""),
        (fixed.replace(" 6*1", " 5*1"), "line", "values"),
    ];
    for (k, (text, line, token)) in cases.iter().enumerate() {
        let file = d.join(format!("bad{k}.fmt"));
        std::fs::write(&file, text).unwrap();
        let o = deform(&d, &["convert", file.to_str().unwrap(), "out.fmt"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "case {k}: {err}");
        assert!(
            err.contains(line) && err.contains(token),
            "case {k}: {line} {token} in {err}"
        );
        assert!(!d.join("out.fmt").exists(), "case {k}");
    }
}
