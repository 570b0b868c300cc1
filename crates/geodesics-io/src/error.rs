//! The one error type of this crate, and the location-only error the parsers
//! produce before the file name is known.

use std::fmt;
use std::path::Path;

use thiserror::Error;

/// Where in a file a defect was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// A 1-based line number (text formats).
    Line(usize),
    /// A 0-based byte offset (binary formats).
    Byte(u64),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(n) => write!(f, "line {n}"),
            Location::Byte(n) => write!(f, "byte {n}"),
        }
    }
}

/// Everything that can go wrong reading a mesh or writing a field.
///
/// Every message is one line and starts with the file it concerns; parse
/// errors add the line (text formats) or byte offset (binary formats), e.g.
/// `bunny.ply: line 17: vertex 3: expected 3 values, found 2`.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum IoError {
    /// The operating system refused a read, write or rename.
    #[error("{file}: {source}")]
    Io {
        /// The file concerned.
        file: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The file has no bytes at all.
    #[error("{file}: the file is empty")]
    Empty {
        /// The file concerned.
        file: String,
    },
    /// Neither the extension nor the content tells which mesh format this is.
    #[error(
        "{file}: unknown mesh format (expected .obj, .ply, .off, .stl, .gltf or .glb, \
         and the content was not recognised)"
    )]
    UnknownFormat {
        /// The file concerned.
        file: String,
    },
    /// A defect at a known place in the file.
    #[error("{file}: {location}: {message}")]
    Parse {
        /// The file concerned.
        file: String,
        /// Line or byte offset of the defect.
        location: Location,
        /// What is wrong there.
        message: String,
    },
    /// A defect of the file as a whole (e.g. the structure of a glTF document).
    #[error("{file}: {message}")]
    Invalid {
        /// The file concerned.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// The output extension is not one of `.txt`, `.csv`, `.npy`, `.ply`.
    #[error("{file}: unknown field format (expected .txt, .csv, .npy or .ply)")]
    UnknownFieldFormat {
        /// The file concerned.
        file: String,
    },
    /// A PLY field was asked for without the mesh to write it on.
    #[error("{file}: writing a PLY field needs the mesh, but none was given")]
    MeshRequired {
        /// The file concerned.
        file: String,
    },
    /// The number of values differs from the number of mesh vertices.
    #[error("{file}: {values} values given for a mesh of {vertices} vertices")]
    LengthMismatch {
        /// The file concerned.
        file: String,
        /// Number of values given.
        values: usize,
        /// Number of mesh vertices.
        vertices: usize,
    },
    /// The output path is one of the inputs: a writer never overwrites its input.
    #[error("refusing to write {file}: it is an input file and would be overwritten")]
    WouldOverwriteInput {
        /// The file concerned.
        file: String,
    },
}

/// A file name for messages: the path as given, on one line.
pub(crate) fn display_name(path: &Path) -> String {
    one_line(&path.display().to_string())
}

/// Replaces line breaks so that every message stays on one line.
pub(crate) fn one_line(s: &str) -> String {
    if s.contains(['\n', '\r']) {
        s.replace(['\n', '\r'], " ")
    } else {
        s.to_owned()
    }
}

/// A parse error before the file name is attached.
#[derive(Debug)]
pub(crate) enum ParseError {
    /// A defect at a place.
    At(Location, String),
    /// A defect of the whole file.
    Whole(String),
}

impl ParseError {
    pub(crate) fn line(line: usize, message: impl Into<String>) -> Self {
        ParseError::At(Location::Line(line), message.into())
    }

    pub(crate) fn byte(offset: usize, message: impl Into<String>) -> Self {
        ParseError::At(Location::Byte(offset as u64), message.into())
    }

    pub(crate) fn whole(message: impl Into<String>) -> Self {
        ParseError::Whole(message.into())
    }

    pub(crate) fn with_file(self, file: String) -> IoError {
        match self {
            ParseError::At(location, message) => IoError::Parse {
                file,
                location,
                message: one_line(&message),
            },
            ParseError::Whole(message) => IoError::Invalid {
                file,
                message: one_line(&message),
            },
        }
    }
}

/// Shows a token from the file in a message: quoted, escaped, shortened.
pub(crate) fn show(token: &[u8]) -> String {
    const MAX: usize = 40;
    let text = String::from_utf8_lossy(&token[..token.len().min(MAX)]);
    let ellipsis = if token.len() > MAX { "..." } else { "" };
    format!("{:?}{ellipsis}", text)
}
