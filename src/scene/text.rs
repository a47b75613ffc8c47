//! Reading a text file whole through a bounded reader: a scene file, a
//! design's requirements file, a measurement manifest and its files. One
//! reader for every front end (the CLI, Python, the measure module), so
//! that a wrong path (a disk image, a device such as `/dev/zero`, an
//! endless pipe) is refused after `limit + 1` bytes instead of being read
//! into memory whole.

use std::io::Read as _;
use std::path::Path;

/// The largest scene file read: 4 MiB. The example scenes are a few
/// hundred bytes. Requirements files (`fpc design`, `fpc.design`) and the
/// scenes a measurement manifest names share the limit.
pub const MAX_SCENE_BYTES: u64 = 4 << 20;

/// Why a text file was not read. The message does not name the file: the
/// caller shows it as its user wrote it.
#[derive(Debug, thiserror::Error)]
pub enum TextFileError {
    /// Opening or reading failed (missing, unreadable, a directory).
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// More than `limit` bytes; `what` names the kind of file ("a scene
    /// file").
    #[error("larger than {}, the limit for {what}", size_text(*.limit))]
    TooLarge { limit: u64, what: &'static str },
    /// Not UTF-8: the offset of the first invalid byte.
    #[error("not UTF-8 text (invalid byte at offset {offset})")]
    NotUtf8 { offset: usize },
}

/// A size in bytes, in MiB too where it is a whole number of them:
/// `4 MiB (4194304 bytes)`.
fn size_text(bytes: u64) -> String {
    const MIB: u64 = 1 << 20;
    if bytes >= MIB && bytes.is_multiple_of(MIB) {
        format!("{} MiB ({bytes} bytes)", bytes / MIB)
    } else {
        format!("{bytes} bytes")
    }
}

/// The text of the file at `path`, at most `limit` bytes of UTF-8 (no more
/// than `limit + 1` bytes are ever read); `what` names the kind of file in
/// the message of [`TextFileError::TooLarge`].
pub fn read_text(path: &Path, limit: u64, what: &'static str) -> Result<String, TextFileError> {
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(TextFileError::TooLarge { limit, what });
    }
    String::from_utf8(bytes).map_err(|e| TextFileError::NotUtf8 {
        offset: e.utf8_error().valid_up_to(),
    })
}

/// The text of the scene (or requirements) file at `path`, at most
/// [`MAX_SCENE_BYTES`].
pub fn read_scene_text(path: &Path) -> Result<String, TextFileError> {
    read_text(path, MAX_SCENE_BYTES, "a scene file")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file holding `bytes` in a directory of its own, removed with it.
    fn temp(name: &str, bytes: &[u8]) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        (dir, p)
    }

    #[test]
    fn a_file_at_the_limit_is_read_and_one_byte_more_is_refused() {
        let (_dir, at) = temp("at.toml", &[b'#'; 16]);
        assert_eq!(read_text(&at, 16, "a test file").unwrap().len(), 16);
        let e = read_text(&at, 15, "a test file").unwrap_err();
        assert_eq!(
            e.to_string(),
            "larger than 15 bytes, the limit for a test file"
        );
    }

    #[test]
    fn the_scene_limit_is_named_in_mib_and_bytes() {
        let e = TextFileError::TooLarge {
            limit: MAX_SCENE_BYTES,
            what: "a scene file",
        };
        assert_eq!(
            e.to_string(),
            "larger than 4 MiB (4194304 bytes), the limit for a scene file"
        );
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_device_is_refused_after_the_limit() {
        let e = read_scene_text(Path::new("/dev/zero")).unwrap_err();
        assert!(matches!(e, TextFileError::TooLarge { .. }), "{e}");
    }

    #[test]
    fn a_directory_a_missing_file_and_bad_utf8_are_errors() {
        let (_dir, bad) = temp("bad.toml", b"a = 1\n\xff");
        let e = read_scene_text(&bad).unwrap_err();
        assert_eq!(e.to_string(), "not UTF-8 text (invalid byte at offset 6)");
        let dir = bad.parent().unwrap();
        assert!(matches!(read_scene_text(dir), Err(TextFileError::Io(_))));
        let missing = dir.join("missing.toml");
        let e = read_scene_text(&missing).unwrap_err();
        assert!(
            matches!(&e, TextFileError::Io(io) if io.kind() == std::io::ErrorKind::NotFound),
            "{e}"
        );
    }
}
