//! All-or-nothing output files.
//!
//! A command that writes several files (a PNG and its AOVs, a folder of Verilog, the
//! trade-off's tables and charts) either replaces all of them or none:
//! 1. every destination is checked first: its folder is created, and a destination that is
//!    a directory, a device or anything but a regular file is refused (nothing written);
//! 2. every file is written to a temporary file beside its destination (`.pixelproc-*`);
//! 3. only when all are written are they renamed into place. An existing destination is
//!    first moved aside, and moved back if a later rename fails.
//!
//! Temporaries are removed on every error path (they are deleted when dropped, and the
//! command line returns from `main` instead of calling `process::exit`). A new file gets the usual
//! mode (`0666` less the umask, so `0644` by default); a replaced file keeps its mode. A
//! destination that is a symlink is followed: the file it points to is replaced and the
//! link stays.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// One pending file.
struct Pending {
    dest: PathBuf,
    tmp: tempfile::NamedTempFile,
}

/// Files to be written together; see the module header.
#[derive(Default)]
pub struct OutputSet {
    files: Vec<Pending>,
}

/// The folder a destination lives in (`.` for a bare file name).
fn folder_of(p: &Path) -> &Path {
    p.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Resolves a symlinked destination to its target and refuses non-regular files.
fn check_dest(path: &Path) -> Result<PathBuf> {
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(path.to_path_buf()),
        Err(e) => Err(e).with_context(|| format!("cannot write {}", path.display())),
        Ok(md) if md.file_type().is_symlink() => {
            let target = std::fs::canonicalize(path)
                .with_context(|| format!("{} is a dangling symlink", path.display()))?;
            check_dest(&target)
        }
        Ok(md) if md.is_dir() => bail!("cannot write {}: it is a directory", path.display()),
        Ok(md) if !md.is_file() => bail!(
            "cannot write {}: it exists and is not a regular file (device, FIFO or socket)",
            path.display()
        ),
        Ok(_) => Ok(path.to_path_buf()),
    }
}

impl OutputSet {
    /// An empty set.
    pub fn new() -> OutputSet {
        OutputSet::default()
    }

    /// Writes `bytes` to a temporary beside `path`; nothing is visible at `path` until
    /// [`OutputSet::commit`].
    pub fn add(&mut self, path: &Path, bytes: &[u8]) -> Result<()> {
        self.add_with(path, |f| {
            use std::io::Write;
            f.write_all(bytes)?;
            Ok(())
        })
    }

    /// Like [`OutputSet::add`], with a writer callback given the temporary's path.
    pub fn add_with(
        &mut self,
        path: &Path,
        write: impl FnOnce(&mut std::fs::File) -> Result<()>,
    ) -> Result<()> {
        if self.files.iter().any(|p| p.dest == path) {
            bail!("{} is named twice among the outputs", path.display());
        }
        let dest = check_dest(path)?;
        let dir = folder_of(&dest);
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create folder {}", dir.display()))?;
        let mut b = tempfile::Builder::new();
        b.prefix(".pixelproc-");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            // The mode given at creation is reduced by the umask, as for any new file.
            b.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let mut tmp = b
            .tempfile_in(dir)
            .with_context(|| format!("cannot write into {}", dir.display()))?;
        write(tmp.as_file_mut()).with_context(|| format!("cannot write {}", path.display()))?;
        tmp.as_file_mut()
            .sync_all()
            .with_context(|| format!("cannot write {}", path.display()))?;
        if let Ok(md) = std::fs::metadata(&dest) {
            std::fs::set_permissions(tmp.path(), md.permissions())
                .with_context(|| format!("cannot keep the mode of {}", dest.display()))?;
        }
        self.files.push(Pending { dest, tmp });
        Ok(())
    }

    /// Renames every temporary into place, or none (see the module header). Returns the
    /// destinations written.
    pub fn commit(self) -> Result<Vec<PathBuf>> {
        let mut backups: Vec<(PathBuf, tempfile::TempPath)> = Vec::new();
        let mut done: Vec<PathBuf> = Vec::new();
        let mut written = Vec::new();
        for p in self.files {
            let dest = p.dest.clone();
            let res = (|| -> Result<()> {
                if dest.exists() {
                    let aside = tempfile::Builder::new()
                        .prefix(".pixelproc-old-")
                        .tempfile_in(folder_of(&dest))?
                        .into_temp_path();
                    std::fs::rename(&dest, &aside)?;
                    backups.push((dest.clone(), aside));
                }
                p.tmp.persist(&dest).map_err(|e| e.error)?;
                Ok(())
            })();
            if let Err(e) = res {
                for d in &done {
                    let _ = std::fs::remove_file(d);
                }
                for (d, aside) in backups {
                    let _ = std::fs::rename(&aside, &d);
                    let _ = aside.keep();
                }
                return Err(e).with_context(|| format!("cannot write {}", dest.display()));
            }
            done.push(dest.clone());
            written.push(dest);
        }
        // Dropping the backups' temp paths deletes the replaced files.
        drop(backups);
        Ok(written)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_is_replaced_when_one_destination_is_bad() {
        let d = tempfile::tempdir().unwrap();
        let a = d.path().join("a.png");
        std::fs::write(&a, b"old").unwrap();
        std::fs::create_dir(d.path().join("b.png")).unwrap();
        let mut o = OutputSet::new();
        o.add(&a, b"new").unwrap();
        let e = o.add(&d.path().join("b.png"), b"x").unwrap_err();
        assert!(e.to_string().contains("is a directory"), "{e}");
        drop(o);
        assert_eq!(std::fs::read(&a).unwrap(), b"old");
        let left: Vec<_> = std::fs::read_dir(d.path()).unwrap().collect();
        assert_eq!(left.len(), 2, "temporaries left behind: {left:?}");
    }

    #[cfg(unix)]
    #[test]
    fn modes_new_and_kept() {
        use std::os::unix::fs::PermissionsExt;
        let d = tempfile::tempdir().unwrap();
        let (a, b) = (d.path().join("a"), d.path().join("b"));
        std::fs::write(&b, b"old").unwrap();
        std::fs::set_permissions(&b, std::fs::Permissions::from_mode(0o640)).unwrap();
        let mut o = OutputSet::new();
        o.add(&a, b"1").unwrap();
        o.add(&b, b"2").unwrap();
        o.commit().unwrap();
        let umask = {
            // Read the umask without changing it for long.
            let m = unsafe { libc::umask(0o022) };
            unsafe { libc::umask(m) };
            m as u32
        };
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&a), 0o666 & !umask);
        assert_eq!(mode(&b), 0o640);
        assert_eq!(std::fs::read(&b).unwrap(), b"2");
    }

    #[cfg(unix)]
    #[test]
    fn symlinks_are_followed_and_devices_refused() {
        let d = tempfile::tempdir().unwrap();
        let target = d.path().join("t.png");
        std::fs::write(&target, b"old").unwrap();
        let link = d.path().join("l.png");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let mut o = OutputSet::new();
        o.add(&link, b"new").unwrap();
        o.commit().unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        let e = OutputSet::new()
            .add(Path::new("/dev/null"), b"x")
            .unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
    }
}
