//! Why a link was refused, in words for the person who opened it.

use super::*;
use std::fmt;

/// Why a link was refused. The Display text is written for the person who opened the link.
#[derive(Clone, Debug, PartialEq)]
pub enum ShareError {
    /// The link is longer than [`MAX_LINK_LEN`].
    TooLong {
        /// Its length in bytes.
        len: usize,
    },
    /// The link does not start with a known version tag.
    UnsupportedVersion(String),
    /// A part is not URL-safe base64 (which part: "settings" or "grid").
    BadBase64(&'static str),
    /// The settings are not the expected JSON (wrong types, missing or unknown fields).
    Malformed(String),
    /// The algorithm name is not one the app has.
    UnknownAlgorithm(String),
    /// The built-in surface name is not one the app has.
    UnknownBuiltin(String),
    /// A surface or file name is empty, too long, or has control characters.
    BadName,
    /// The file fingerprint's hash is not 16 hex digits, or its size is out of range.
    BadFingerprint(String),
    /// The import choice of a file fingerprint is invalid (unknown projection, bad grid size).
    BadImport(String),
    /// The run parameters are out of range.
    InvalidParams(String),
    /// A number is out of its range or not finite (which field, and what is allowed).
    OutOfRange {
        /// The field.
        field: &'static str,
        /// What is allowed.
        allowed: String,
    },
    /// The embedded grid's sides are out of range.
    BadGridSize {
        /// Its width.
        width: usize,
        /// Its height.
        height: usize,
    },
    /// The link names an embedded grid but carries none.
    MissingGrid,
    /// The link carries grid data but its surface is not an embedded grid.
    UnexpectedGrid,
    /// The grid data inflates to more than its dimensions allow.
    GridTooLarge,
    /// The grid data is not valid deflate data.
    CorruptGrid,
    /// The grid data's byte count does not match its dimensions.
    GridLengthMismatch {
        /// Bytes the dimensions call for.
        expected: usize,
        /// Bytes found.
        found: usize,
    },
    /// A height of the grid is NaN or infinite.
    NonFiniteHeight {
        /// Its row-major index.
        index: usize,
    },
    /// The grid is not a valid height field.
    BadGrid(String),
    /// The embedded grid's geometry (origin, spacing, placement, georeference) is invalid.
    BadGeometry(String),
}

/// At most `max` characters of `s`, for echoing hostile input in a message.
pub(super) fn clip(s: &str, max: usize) -> String {
    let mut out: String = s.chars().take(max).collect();
    if s.chars().nth(max).is_some() {
        out.push('…');
    }
    out
}

impl fmt::Display for ShareError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "This share link cannot be opened: ")?;
        match self {
            Self::TooLong { len } => write!(
                f,
                "it is {len} characters long, more than the {MAX_LINK_LEN} allowed."
            ),
            Self::UnsupportedVersion(v) => write!(
                f,
                "it does not start with \"{VERSION}.\" (found \"{}\"); it may come from another version of the app or be cut short.",
                clip(v, 16)
            ),
            Self::BadBase64(part) => write!(
                f,
                "its {part} part is corrupt (not URL-safe base64); it may have been cut or altered."
            ),
            Self::Malformed(m) => write!(f, "its settings are malformed ({}).", clip(m, 120)),
            Self::UnknownAlgorithm(a) => write!(
                f,
                "it names an unknown algorithm \"{}\" (known: nsga2, weighted, greedy, decimation).",
                clip(a, 40)
            ),
            Self::UnknownBuiltin(s) => write!(
                f,
                "it names an unknown built-in surface \"{}\" (known: {}).",
                clip(s, 40),
                loader::BUILTINS.map(|b| b.name).join(", ")
            ),
            Self::BadName => write!(
                f,
                "its surface name is empty, longer than {MAX_NAME_LEN} bytes, or has control characters."
            ),
            Self::BadFingerprint(m) => write!(f, "its file fingerprint is invalid: {m}."),
            Self::BadImport(m) => write!(
                f,
                "its choice of how to turn the file into a grid is invalid: {}.",
                clip(m, 120)
            ),
            Self::InvalidParams(m) => write!(f, "its run parameters are invalid: {m}."),
            Self::OutOfRange { field, allowed } => {
                write!(f, "its {field} is out of range (allowed: {allowed}).")
            }
            Self::BadGridSize { width, height } => write!(
                f,
                "its embedded grid is {width}×{height}; sides must be 2 to {MAX_EMBEDDED_SIDE}."
            ),
            Self::MissingGrid => write!(f, "it should carry a grid but has none."),
            Self::UnexpectedGrid => write!(f, "it carries grid data its surface does not use."),
            Self::GridTooLarge => write!(
                f,
                "its embedded grid inflates to more data than its dimensions allow."
            ),
            Self::CorruptGrid => write!(f, "its embedded grid data is corrupt."),
            Self::GridLengthMismatch { expected, found } => write!(
                f,
                "its embedded grid has {found} bytes where its dimensions call for {expected}."
            ),
            Self::NonFiniteHeight { index } => write!(
                f,
                "its embedded grid has a NaN or infinite height at point {index}."
            ),
            Self::BadGrid(m) => write!(f, "its embedded grid is invalid: {m}."),
            Self::BadGeometry(m) => write!(
                f,
                "its embedded grid's placement (origin, spacing or georeference) is invalid: {}.",
                clip(m, 160)
            ),
        }
    }
}

impl std::error::Error for ShareError {}
