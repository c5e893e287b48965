//! Reading input files (scene JSON, OBJ meshes) under explicit rules.
//!
//! Scenes are often handed around, and a renderer run in long unattended sweeps must not
//! hang on a FIFO, read `/dev/zero` until memory runs out, or wander out of a scene's
//! folder when asked not to. The rules, in one place:
//! - only **regular files** are read (a symlink to a regular file is fine); a FIFO, socket,
//!   device or directory is an error naming the path and what it is;
//! - a file larger than [`ReadPolicy::max_bytes`] is refused before it is read (the limit is
//!   also enforced while reading, so a file growing underneath cannot get past it);
//! - text must be UTF-8; a leading UTF-8 byte-order mark is skipped;
//! - with [`ReadPolicy::sandbox`] set, a mesh path must resolve (after `..` and symlinks)
//!   to a file inside that folder; otherwise absolute paths and `../` are allowed.

use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Default largest input file: 256 MiB (about 10 million OBJ triangles).
pub const DEFAULT_MAX_INPUT_BYTES: u64 = 256 << 20;

/// How input files may be read.
#[derive(Clone, Debug)]
pub struct ReadPolicy {
    /// Largest accepted file, in bytes.
    pub max_bytes: u64,
    /// When set, mesh files must lie inside this folder.
    pub sandbox: Option<PathBuf>,
}

impl Default for ReadPolicy {
    fn default() -> Self {
        ReadPolicy {
            max_bytes: DEFAULT_MAX_INPUT_BYTES,
            sandbox: None,
        }
    }
}

/// Why an input file was not read.
#[derive(Debug, Error)]
pub enum InputError {
    /// The file could not be opened or read.
    #[error("cannot read {}", path.display())]
    Io {
        /// Path.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// The path names something other than a regular file.
    #[error("{} is {kind}, not a regular file", path.display())]
    NotRegular {
        /// Path.
        path: PathBuf,
        /// What it is.
        kind: FileKind,
    },
    /// The file is larger than the policy allows.
    #[error("{} is {size} bytes, over the {max}-byte input limit (raise it with --max-input-mb)", path.display())]
    TooLarge {
        /// Path.
        path: PathBuf,
        /// Its size (or the bytes read before giving up).
        size: u64,
        /// The limit.
        max: u64,
    },
    /// The file is not UTF-8 text.
    #[error("{} is not UTF-8 text (byte {offset})", path.display())]
    NotUtf8 {
        /// Path.
        path: PathBuf,
        /// Offset of the first invalid byte.
        offset: usize,
    },
    /// A mesh path leaves the sandbox folder.
    #[error("{} lies outside the scene folder {} (--sandbox)", path.display(), root.display())]
    OutsideSandbox {
        /// Path.
        path: PathBuf,
        /// The sandbox folder.
        root: PathBuf,
    },
}

/// What a non-regular path is, for messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A directory.
    Directory,
    /// A named pipe.
    Fifo,
    /// A character or block device.
    Device,
    /// A socket.
    Socket,
    /// Anything else.
    Other,
}

impl fmt::Display for FileKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FileKind::Directory => "a directory",
            FileKind::Fifo => "a FIFO (named pipe)",
            FileKind::Device => "a device",
            FileKind::Socket => "a socket",
            FileKind::Other => "not a file",
        })
    }
}

fn kind_of(ft: std::fs::FileType) -> FileKind {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_fifo() {
            return FileKind::Fifo;
        }
        if ft.is_char_device() || ft.is_block_device() {
            return FileKind::Device;
        }
        if ft.is_socket() {
            return FileKind::Socket;
        }
    }
    if ft.is_dir() {
        FileKind::Directory
    } else {
        FileKind::Other
    }
}

/// Reads a text file under `policy` (regular file, size limit, UTF-8, BOM skipped). The
/// sandbox is not applied here: see [`resolve_in_sandbox`].
pub fn read_text(path: &Path, policy: &ReadPolicy) -> Result<String, InputError> {
    let io = |e| InputError::Io {
        path: path.to_path_buf(),
        source: e,
    };
    // `metadata` follows symlinks and never opens the file, so a FIFO cannot block here.
    let md = std::fs::metadata(path).map_err(io)?;
    if !md.is_file() {
        return Err(InputError::NotRegular {
            path: path.to_path_buf(),
            kind: kind_of(md.file_type()),
        });
    }
    let too_large = |size| InputError::TooLarge {
        path: path.to_path_buf(),
        size,
        max: policy.max_bytes,
    };
    if md.len() > policy.max_bytes {
        return Err(too_large(md.len()));
    }
    let f = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(md.len() as usize);
    f.take(policy.max_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > policy.max_bytes {
        return Err(too_large(bytes.len() as u64));
    }
    decode_text(bytes, path)
}

/// UTF-8 decoding with a leading byte-order mark skipped.
pub fn decode_text(mut bytes: Vec<u8>, path: &Path) -> Result<String, InputError> {
    if bytes.starts_with(&[0xEF, 0xBB, 0xBF]) {
        bytes.drain(..3);
    }
    String::from_utf8(bytes).map_err(|e| InputError::NotUtf8 {
        path: path.to_path_buf(),
        offset: e.utf8_error().valid_up_to(),
    })
}

/// Joins `rel` to `dir` and, when the policy has a sandbox, checks that the result resolves
/// (after `..` and symlinks) inside it.
pub fn resolve_in_sandbox(
    dir: &Path,
    rel: &str,
    policy: &ReadPolicy,
) -> Result<PathBuf, InputError> {
    let p = dir.join(rel);
    let Some(root) = &policy.sandbox else {
        return Ok(p);
    };
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |e| InputError::Io { path, source: e }
    };
    let root_c = std::fs::canonicalize(root).map_err(io(root))?;
    let p_c = std::fs::canonicalize(&p).map_err(io(&p))?;
    if p_c.starts_with(&root_c) {
        Ok(p_c)
    } else {
        Err(InputError::OutsideSandbox {
            path: p,
            root: root.to_path_buf(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scratch directory removed when the test ends, passed or failed.
    fn tmp() -> tempfile::TempDir {
        tempfile::tempdir().unwrap()
    }

    #[test]
    fn bom_is_skipped_and_bad_utf8_named() {
        let p = Path::new("x.json");
        assert_eq!(decode_text(b"\xEF\xBB\xBF{}".to_vec(), p).unwrap(), "{}");
        let e = decode_text(b"ab\xFFc".to_vec(), p).unwrap_err().to_string();
        assert!(e.contains("not UTF-8") && e.contains("byte 2"), "{e}");
    }

    #[test]
    fn directories_and_devices_are_refused() {
        let t = tmp();
        let d = t.path();
        let e = read_text(d, &ReadPolicy::default()).unwrap_err();
        assert!(matches!(
            e,
            InputError::NotRegular {
                kind: FileKind::Directory,
                ..
            }
        ));
        #[cfg(unix)]
        {
            let e = read_text(Path::new("/dev/zero"), &ReadPolicy::default()).unwrap_err();
            assert!(
                matches!(
                    e,
                    InputError::NotRegular {
                        kind: FileKind::Device,
                        ..
                    }
                ),
                "{e}"
            );
        }
    }

    #[test]
    fn size_limit_is_enforced() {
        let t = tmp();
        let p = t.path().join("big.obj");
        std::fs::write(&p, vec![b'#'; 100]).unwrap();
        let pol = ReadPolicy {
            max_bytes: 99,
            sandbox: None,
        };
        let e = read_text(&p, &pol).unwrap_err().to_string();
        assert!(
            e.contains("100 bytes") && e.contains("--max-input-mb"),
            "{e}"
        );
        let pol = ReadPolicy {
            max_bytes: 100,
            sandbox: None,
        };
        assert_eq!(read_text(&p, &pol).unwrap().len(), 100);
    }

    #[test]
    fn sandbox_keeps_paths_inside() {
        let t = tmp();
        let d = t.path().join("sb");
        std::fs::create_dir_all(d.join("in")).unwrap();
        std::fs::write(d.join("in/a.obj"), "v 0 0 0").unwrap();
        std::fs::write(d.join("b.obj"), "v 0 0 0").unwrap();
        let pol = ReadPolicy {
            max_bytes: 1000,
            sandbox: Some(d.join("in")),
        };
        assert!(resolve_in_sandbox(&d.join("in"), "a.obj", &pol).is_ok());
        let e = resolve_in_sandbox(&d.join("in"), "../b.obj", &pol).unwrap_err();
        assert!(matches!(e, InputError::OutsideSandbox { .. }), "{e}");
        let abs = d.join("b.obj");
        let e = resolve_in_sandbox(&d.join("in"), abs.to_str().unwrap(), &pol).unwrap_err();
        assert!(matches!(e, InputError::OutsideSandbox { .. }), "{e}");
        let open = ReadPolicy::default();
        assert!(resolve_in_sandbox(&d.join("in"), "../b.obj", &open).is_ok());
    }
}
