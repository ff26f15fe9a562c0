//! The one error type of the file readers: where it happened and what was expected.

use std::fmt;

/// Where in the input a problem was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// A 1-based line number (text formats).
    Line(usize),
    /// A 0-based byte offset (binary formats).
    Byte(u64),
    /// The file as a whole (for example a size that fits no layout).
    File,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(n) => write!(f, "line {n}"),
            Location::Byte(n) => write!(f, "byte {n}"),
            Location::File => write!(f, "file"),
        }
    }
}

/// What went wrong while reading a mesh or grid file.
#[non_exhaustive]
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FormatErrorKind {
    /// The input ended while something was still expected.
    UnexpectedEof {
        /// What was expected.
        expected: String,
    },
    /// A token or line is not what the format requires here.
    Expected {
        /// What was expected.
        expected: String,
        /// What was found (shortened and escaped).
        found: String,
    },
    /// A coordinate or value is NaN or infinite.
    NotFinite {
        /// Which value.
        what: String,
        /// The value as found.
        found: String,
    },
    /// An element type code that the format or the mesh dimension does not allow.
    BadElement {
        /// The code found.
        code: i64,
        /// What was allowed here.
        allowed: String,
    },
    /// A node index is not smaller than the number of points.
    IndexOutOfRange {
        /// The index found.
        index: u64,
        /// The number of points.
        bound: usize,
    },
    /// An element lists the same node twice.
    RepeatedNode {
        /// The repeated node.
        node: u64,
    },
    /// A keyword that may appear once appears again.
    Duplicate {
        /// The keyword.
        keyword: String,
    },
    /// A required section never appeared.
    Missing {
        /// The missing keyword or section.
        keyword: String,
    },
    /// A valid feature of the format that this reader does not support.
    Unsupported {
        /// The feature.
        what: String,
    },
    /// No layout fits the data (Plot3D auto-detection), with the closest explanation.
    NoLayout {
        /// Why the closest candidate failed.
        reason: String,
    },
    /// Several layouts fit the data equally well.
    Ambiguous {
        /// The layouts that fit.
        candidates: Vec<String>,
    },
    /// A count or size is too large to be real (or overflows).
    TooLarge {
        /// What is too large.
        what: String,
        /// Its value.
        value: u64,
    },
}

/// A read error: a [`Location`] and a [`FormatErrorKind`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FormatError {
    /// Where.
    pub location: Location,
    /// What.
    pub kind: FormatErrorKind,
}

impl FormatError {
    /// Builds an error at `location`.
    pub fn new(location: Location, kind: FormatErrorKind) -> Self {
        FormatError { location, kind }
    }

    /// "expected X, found Y" at a line.
    pub fn expected_at_line(line: usize, expected: impl Into<String>, found: &[u8]) -> Self {
        FormatError::new(
            Location::Line(line),
            FormatErrorKind::Expected {
                expected: expected.into(),
                found: show(found),
            },
        )
    }

    /// "unexpected end of file, expected X" at a line.
    pub fn eof_at_line(line: usize, expected: impl Into<String>) -> Self {
        FormatError::new(
            Location::Line(line),
            FormatErrorKind::UnexpectedEof {
                expected: expected.into(),
            },
        )
    }

    /// The 1-based line number, for text formats.
    pub fn line(&self) -> Option<usize> {
        match self.location {
            Location::Line(n) => Some(n),
            _ => None,
        }
    }
}

/// Shows up to 40 characters of a token, escaped, for error messages.
pub fn show(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        return "nothing".to_string();
    }
    let cut = &bytes[..bytes.len().min(40)];
    let s = String::from_utf8_lossy(cut);
    let mut out = format!("{s:?}");
    if bytes.len() > 40 {
        out.push('…');
    }
    out
}

impl fmt::Display for FormatErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FormatErrorKind::UnexpectedEof { expected } => {
                write!(f, "unexpected end of file, expected {expected}")
            }
            FormatErrorKind::Expected { expected, found } => {
                write!(f, "expected {expected}, found {found}")
            }
            FormatErrorKind::NotFinite { what, found } => {
                write!(f, "{what} is not a finite number: {found}")
            }
            FormatErrorKind::BadElement { code, allowed } => {
                write!(f, "bad element type code {code}, expected {allowed}")
            }
            FormatErrorKind::IndexOutOfRange { index, bound } => write!(
                f,
                "node index {index} is out of range, expected an index below {bound} (0-based)"
            ),
            FormatErrorKind::RepeatedNode { node } => {
                write!(f, "element lists node {node} twice")
            }
            FormatErrorKind::Duplicate { keyword } => {
                write!(f, "{keyword} appears twice, expected it once")
            }
            FormatErrorKind::Missing { keyword } => write!(f, "missing {keyword}"),
            FormatErrorKind::Unsupported { what } => write!(f, "not supported: {what}"),
            FormatErrorKind::NoLayout { reason } => write!(f, "{reason}"),
            FormatErrorKind::Ambiguous { candidates } => write!(
                f,
                "ambiguous layout, {} interpretations fit ({}); choose one with the layout options",
                candidates.len(),
                candidates.join("; ")
            ),
            FormatErrorKind::TooLarge { what, value } => {
                write!(f, "{what} = {value} is too large for this file")
            }
        }
    }
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.location {
            Location::File => write!(f, "{}", self.kind),
            loc => write!(f, "{loc}: {}", self.kind),
        }
    }
}

impl std::error::Error for FormatError {}
