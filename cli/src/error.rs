//! The tool's one error type: every command returns it, `main` prints it on one line and
//! exits with [`CliError::exit_code`]. File and kernel errors keep their typed cause as
//! [`std::error::Error::source`].

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use crate::formats::FormatError;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// An input file is malformed.
    Read {
        /// The file.
        path: PathBuf,
        /// What is wrong, and where.
        source: FormatError,
    },
    /// A file could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// The system error.
        source: io::Error,
    },
    /// The inputs are well-formed but do not fit together (a missing marker, a 3D rotation on
    /// a 2D mesh, …).
    Invalid(String),
    /// The kernel reported an error (kept as the [`std::error::Error::source`]).
    Kernel {
        /// Where: the file, block and step (e.g. `m.su2: graph`).
        context: String,
        /// The kernel's typed error.
        source: deform_kernel::Error,
    },
    /// The work would not fit in the memory available.
    TooLarge {
        /// The file.
        path: PathBuf,
        /// How much is needed and available.
        message: String,
    },
    /// The output would have cells that the input did not have inverted or folded; nothing
    /// was written (`--allow-folds` writes it and reports them). Exit status 4.
    Folded(String),
    /// A solve stopped before it converged; nothing was written (`--allow-unconverged` writes
    /// the result and reports it). Exit status 5.
    Unconverged(String),
    /// This build does not have what the command needs yet.
    NotAvailable {
        /// The command or option.
        feature: &'static str,
        /// The missing part.
        needs: &'static str,
    },
}

impl CliError {
    /// Names the input file in a kernel error (other errors already name their file).
    pub fn in_file(self, path: &Path) -> CliError {
        match self {
            CliError::Kernel { context, source } => CliError::Kernel {
                context: format!("{}: {context}", path.display()),
                source,
            },
            e => e,
        }
    }

    /// Adds `prefix` (e.g. `block 2`) to a kernel error's context.
    pub fn within(self, prefix: &str) -> CliError {
        match self {
            CliError::Kernel { context, source } => CliError::Kernel {
                context: format!("{prefix}: {context}"),
                source,
            },
            e => e,
        }
    }

    /// The process exit status: 3 for [`CliError::NotAvailable`] and for a file format feature
    /// the reader does not support, 4 for [`CliError::Folded`], 5 for
    /// [`CliError::Unconverged`], 1 otherwise (clap uses 2 for a bad command line, signals
    /// 128 + the signal number).
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::NotAvailable { .. } => 3,
            // A valid feature of the file format that the reader does not support.
            CliError::Read { source, .. }
                if matches!(
                    source.kind,
                    crate::formats::FormatErrorKind::Unsupported { .. }
                ) =>
            {
                3
            }
            CliError::Folded(_) => 4,
            CliError::Unconverged(_) => 5,
            _ => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Read { path, source } => write!(f, "{}: {source}", path.display()),
            CliError::Io { path, source } => write!(f, "{}: {source}", path.display()),
            CliError::Invalid(m) | CliError::Folded(m) | CliError::Unconverged(m) => {
                write!(f, "{m}")
            }
            CliError::Kernel { context, source } => write!(f, "kernel: {context}: {source}"),
            CliError::TooLarge { path, message } => write!(f, "{}: {message}", path.display()),
            CliError::NotAvailable { feature, needs } => {
                write!(f, "{feature}: not available yet: needs {needs}")
            }
        }
    }
}

impl std::error::Error for CliError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            CliError::Read { source, .. } => Some(source),
            CliError::Io { source, .. } => Some(source),
            CliError::Kernel { source, .. } => Some(source),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernel_errors_keep_their_typed_source_and_gain_context() {
        let e = CliError::Kernel {
            context: "graph".into(),
            source: deform_kernel::Error::InvalidParameter {
                arg: "direction",
                reason: "must be 0, 1 or 2",
            },
        }
        .within("block 2")
        .in_file(Path::new("m.x"));
        assert!(
            e.to_string().starts_with("kernel: m.x: block 2: graph: "),
            "{e}"
        );
        let source = std::error::Error::source(&e).expect("a source");
        let kernel = source
            .downcast_ref::<deform_kernel::Error>()
            .expect("the kernel's error");
        assert_eq!(
            *kernel,
            deform_kernel::Error::InvalidParameter {
                arg: "direction",
                reason: "must be 0, 1 or 2"
            }
        );
        assert_eq!(e.exit_code(), 1);
    }
}
