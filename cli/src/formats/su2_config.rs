//! SU2 configuration files (`KEY= value` lines, `%` comments), as `SU2_DEF` reads them.
//!
//! Only the syntax lives here: keys (upper-cased, as SU2 compares them), values as written, the
//! line of each, and the list forms SU2 uses (`( a, b )`, and `;` between the parameter groups
//! of several design variables). What the options mean is `deform su2`'s business.

use super::error::{FormatError, FormatErrorKind, Location};

/// One `KEY= value` line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConfigEntry {
    /// The key, upper-cased.
    pub key: String,
    /// The value, trimmed (comments removed).
    pub value: String,
    /// 1-based line number.
    pub line: usize,
}

/// A whole configuration file: its entries in file order, each key once.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Su2Config {
    /// The entries.
    pub entries: Vec<ConfigEntry>,
}

impl Su2Config {
    /// The entry of `key` (upper case), if the file sets it.
    pub fn get(&self, key: &str) -> Option<&ConfigEntry> {
        self.entries.iter().find(|e| e.key == key)
    }
}

/// Reads a configuration file. Every line is blank, a `%` comment, or `KEY= value` with a key
/// of letters, digits and underscores; a key given twice is an error (SU2 refuses it too).
pub fn parse_su2_config(bytes: &[u8]) -> Result<Su2Config, FormatError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        FormatError::expected_at_line(line, "UTF-8 text", &[])
    })?;
    let mut config = Su2Config::default();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let content = raw.split('%').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let Some((key, value)) = content.split_once('=') else {
            return Err(FormatError::expected_at_line(
                line,
                "`KEY= value` or a `%` comment",
                content.as_bytes(),
            ));
        };
        let key = key.trim().to_ascii_uppercase();
        if key.is_empty() || !key.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_') {
            return Err(FormatError::expected_at_line(
                line,
                "an option name (letters, digits, `_`) before `=`",
                content.as_bytes(),
            ));
        }
        if let Some(first) = config.get(&key) {
            return Err(FormatError::new(
                Location::Line(line),
                FormatErrorKind::Duplicate {
                    keyword: format!("{key} (first set at line {})", first.line),
                },
            ));
        }
        config.entries.push(ConfigEntry {
            key,
            value: value.trim().to_string(),
            line,
        });
    }
    Ok(config)
}

/// The items of a list value: `( a, b c )`, `a, b` or `a` (parentheses optional; commas
/// and blanks separate).
pub fn list_items(value: &str) -> Vec<&str> {
    let inner = value.trim();
    let inner = inner.strip_prefix('(').unwrap_or(inner);
    let inner = inner.strip_suffix(')').unwrap_or(inner);
    inner
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .collect()
}

/// The groups of a `;`-separated value (`DV_PARAM= ( 1, 0.5 ); ( 0, 0.05 )`), each a list.
pub fn list_groups(value: &str) -> Vec<Vec<&str>> {
    value.split(';').map(list_items).collect()
}
