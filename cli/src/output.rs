//! Output files that appear whole or not at all: each is written to a hidden temporary file in
//! the target directory and renamed into place only when every output of the command is ready.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// A set of outputs staged in temporary files; [`Staged::commit`] renames them all into place,
/// dropping without committing removes them.
#[derive(Debug, Default)]
pub struct Staged {
    files: Vec<(PathBuf, PathBuf)>,
}

fn temp_path(target: &Path) -> PathBuf {
    let dir = target
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    dir.join(format!(".{name}.deform-tmp-{}", std::process::id()))
}

impl Staged {
    /// No files yet.
    pub fn new() -> Self {
        Staged::default()
    }

    /// Writes a file through `write` into a temporary file next to `target`. On error the
    /// temporary file is removed and the error returned.
    pub fn write<F>(&mut self, target: &Path, write: F) -> io::Result<()>
    where
        F: FnOnce(&mut fs::File) -> io::Result<()>,
    {
        if target.is_dir() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{} is a directory", target.display()),
            ));
        }
        if let Some(input) = crate::guard::is_input(target) {
            return Err(io::Error::new(
                io::ErrorKind::AlreadyExists,
                format!(
                    "{} is the input file {}; refusing to overwrite an input",
                    target.display(),
                    input.display()
                ),
            ));
        }
        let tmp = temp_path(target);
        crate::guard::register_temp(&tmp);
        let result = (|| {
            let mut f = fs::File::create(&tmp)?;
            write(&mut f)?;
            f.flush()?;
            f.sync_all()
        })();
        match result {
            Ok(()) => {
                self.files.push((tmp, target.to_path_buf()));
                Ok(())
            }
            Err(e) => {
                let _ = fs::remove_file(&tmp);
                crate::guard::forget_temp(&tmp);
                Err(e)
            }
        }
    }

    /// Renames every staged file into place.
    pub fn commit(mut self) -> io::Result<()> {
        let files = std::mem::take(&mut self.files);
        let mut iter = files.into_iter();
        while let Some((tmp, target)) = iter.next() {
            let renamed = fs::rename(&tmp, &target);
            crate::guard::forget_temp(&tmp);
            if let Err(e) = renamed {
                let _ = fs::remove_file(&tmp);
                for (t, _) in iter {
                    let _ = fs::remove_file(&t);
                    crate::guard::forget_temp(&t);
                }
                return Err(io::Error::new(
                    e.kind(),
                    format!("cannot create {}: {e}", target.display()),
                ));
            }
        }
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        for (tmp, _) in self.files.drain(..) {
            let _ = fs::remove_file(&tmp);
            crate::guard::forget_temp(&tmp);
        }
    }
}
