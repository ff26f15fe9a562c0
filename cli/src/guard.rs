//! What protects the user's files: an output that is an input is refused before anything is
//! read, temporary output files are removed when the process is interrupted (SIGINT, SIGTERM,
//! SIGHUP), and a mesh that would not fit in memory is refused up front ("needs N GiB") instead
//! of aborting half-way.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::CliError;

/// True when `a` and `b` name the same existing file, also through symbolic or hard links
/// (same device and inode on Unix; equal canonical paths elsewhere).
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
    }
}

/// Refuses outputs that are inputs (or each other). Call it before reading anything.
pub fn check_outputs(inputs: &[&Path], outputs: &[&Path]) -> Result<(), CliError> {
    for (k, out) in outputs.iter().enumerate() {
        if let Some(input) = inputs.iter().find(|i| *i == out || same_file(i, out)) {
            return Err(CliError::Invalid(format!(
                "{}: this output is the input file {}; refusing to overwrite an input (choose another output name)",
                out.display(),
                input.display()
            )));
        }
        if let Some(other) = outputs[..k].iter().find(|o| *o == out || same_file(o, out)) {
            return Err(CliError::Invalid(format!(
                "{}: named twice as an output (also {})",
                out.display(),
                other.display()
            )));
        }
    }
    Ok(())
}

/// Inputs of the running command, for the last-moment check in [`crate::output::Staged`].
static INPUTS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Remembers the command's input files (see [`is_input`]).
pub fn register_inputs(inputs: &[&Path]) {
    if let Ok(mut v) = INPUTS.lock() {
        v.extend(inputs.iter().map(|p| p.to_path_buf()));
    }
}

/// The registered input that `target` would overwrite, if any (catches derived output names
/// such as `OUT_b2.vts` that [`check_outputs`] cannot see in advance).
pub fn is_input(target: &Path) -> Option<PathBuf> {
    let v = INPUTS.lock().ok()?;
    v.iter().find(|i| same_file(i, target)).cloned()
}

/// Temporary output files that exist right now; removed on SIGINT/SIGTERM/SIGHUP.
static TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Registers a temporary file before it is created.
pub fn register_temp(path: &Path) {
    if let Ok(mut v) = TEMPS.lock() {
        v.push(path.to_path_buf());
    }
}

/// Forgets a temporary file (renamed into place or removed).
pub fn forget_temp(path: &Path) {
    if let Ok(mut v) = TEMPS.lock() {
        v.retain(|p| p != path);
    }
}

/// Starts a thread that, on SIGINT, SIGTERM or SIGHUP, removes every registered temporary file
/// and exits with status 128 + the signal number (the shell's convention). The previous
/// contents of every output stay intact: outputs are only ever renamed into place whole.
pub fn install_signal_cleanup() -> std::io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            if let Ok(v) = TEMPS.lock() {
                for p in v.iter() {
                    let _ = std::fs::remove_file(p);
                }
            }
            eprintln!("deform: interrupted (signal {sig}); no output was changed");
            std::process::exit(128 + sig);
        }
    });
    Ok(())
}

/// Bytes of memory the tool may use: the kernel's `MemAvailable`, lowered by the environment
/// variable `DEFORM_MEMORY_LIMIT` (bytes) when set. `None` when neither is known.
pub fn available_memory() -> Option<u64> {
    let from_env = std::env::var("DEFORM_MEMORY_LIMIT")
        .ok()
        .and_then(|s| s.trim().parse::<u64>().ok());
    let from_proc = std::fs::read_to_string("/proc/meminfo").ok().and_then(|s| {
        s.lines()
            .find_map(|l| l.strip_prefix("MemAvailable:"))
            .and_then(|rest| {
                rest.trim()
                    .trim_end_matches("kB")
                    .trim()
                    .parse::<u64>()
                    .ok()
            })
            .map(|kib| kib.saturating_mul(1024))
    });
    match (from_env, from_proc) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

fn gib(bytes: u64) -> f64 {
    bytes as f64 / (1u64 << 30) as f64
}

/// Refuses work on `path` that needs an estimated `bytes` of memory when less is available.
pub fn check_memory(path: &Path, what: &str, bytes: u64) -> Result<(), CliError> {
    match available_memory() {
        Some(avail) if bytes > avail => Err(CliError::TooLarge {
            path: path.to_path_buf(),
            message: format!(
                "{what} needs about {:.2} GiB of memory, {:.2} GiB available",
                gib(bytes),
                gib(avail)
            ),
        }),
        _ => Ok(()),
    }
}

/// Reads a whole file after checking that it fits: the buffer is reserved with `try_reserve`,
/// so an allocation the system refuses is an error, not an abort.
pub fn read_file(path: &Path) -> Result<Vec<u8>, CliError> {
    use std::io::Read;
    let io = |source| CliError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut f = std::fs::File::open(path).map_err(io)?;
    let len = f.metadata().map_err(io)?.len();
    check_memory(path, "reading this file", len)?;
    let mut buf = Vec::new();
    let want = usize::try_from(len).unwrap_or(usize::MAX);
    buf.try_reserve_exact(want)
        .map_err(|_| CliError::TooLarge {
            path: path.to_path_buf(),
            message: format!("reading this file needs {:.2} GiB of memory", gib(len)),
        })?;
    f.read_to_end(&mut buf).map_err(io)?;
    Ok(buf)
}

/// Estimated peak bytes of `deform move` on a mesh: measured peaks on a 234k-node NACA mesh
/// (docs/amg.md) are 365 bytes a node for springs with AMG and 660 for the quaternion method
/// with AMG (points, displacements, graph, stiffness, hierarchy, solver vectors, quality);
/// 800 a node plus 48 a cell-node leave a margin.
pub fn move_estimate(nodes: usize, cell_nodes: usize) -> u64 {
    (nodes as u64)
        .saturating_mul(800)
        .saturating_add((cell_nodes as u64).saturating_mul(48))
}

/// Estimated peak bytes of `deform mesh` for `nodes` points (the product of the requested
/// sizes, saturating): the generator's points and cells, the SU2 copy and the output buffer
/// take under 400 bytes a node on the hexahedral blocks (3D, 8 cell nodes a node).
pub fn mesh_estimate(sizes: &[usize]) -> u64 {
    sizes
        .iter()
        .fold(1u64, |n, &s| n.saturating_mul(s as u64))
        .saturating_mul(400)
}
