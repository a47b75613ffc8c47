//! Scene arguments: TOML text or a path to a scene file, read and
//! resolved as `fpc solve` reads them, and file errors as Python's own.

use std::path::Path;

use fpc::scene::TextFileError;
use pyo3::exceptions::{PyOSError, PyTypeError};
use pyo3::prelude::*;

use crate::errors::from_scene_read;

/// True when a `str` scene argument is meant as a path, not TOML text: a
/// single line that ends in `.toml` or contains a path separator (`/`, or
/// `\\` on Windows). TOML text of one line has a `=` or a `[` before any
/// of these (`a = "x/y.toml"`), so those stay text.
pub fn looks_like_path(s: &str) -> bool {
    if s.is_empty() || s.contains('\n') {
        return false;
    }
    let t = s.trim();
    let sep = t.contains('/') || (cfg!(windows) && t.contains('\\'));
    let toml_like = t.starts_with('[') || t.contains('=');
    (t.to_ascii_lowercase().ends_with(".toml") || sep) && !toml_like
}

/// A scene argument: TOML text, or a path to a scene file (any
/// `os.PathLike`, or a `str` that [`looks_like_path`]). Returns the text
/// and the path shown in messages (empty for text). A path that does not
/// exist is `FileNotFoundError` naming it (never parsed as TOML); a file
/// that cannot be read (a directory, larger than the library's
/// [`fpc::scene::MAX_SCENE_BYTES`], not UTF-8) an `OSError` naming it in
/// `.filename` and its message.
pub fn scene_text(obj: &Bound<'_, PyAny>) -> PyResult<(String, String)> {
    let py = obj.py();
    let os = py.import("os")?;
    let is_pathlike = obj.is_instance(&os.getattr("PathLike")?)?;
    let path: Option<String> = if is_pathlike {
        Some(
            os.call_method1("fspath", (obj,))?
                .extract()
                .map_err(|_| PyTypeError::new_err("a scene path must be a str path, not bytes"))?,
        )
    } else {
        let s: String = obj.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "a scene is TOML text or a path to a scene file (str or os.PathLike), not {}",
                obj.get_type()
                    .name()
                    .map(|n| n.to_string())
                    .unwrap_or_default()
            ))
        })?;
        (looks_like_path(&s) || (!s.contains('\n') && !s.is_empty() && Path::new(&s).is_file()))
            .then_some(s)
    };
    match path {
        Some(p) => {
            let text = fpc::scene::read_scene_text(Path::new(&p)).map_err(|e| {
                io_error(py, &e, format!("cannot read the scene file {p}: {e}"), &p)
            })?;
            Ok((text, p))
        }
        None => Ok((obj.extract()?, String::new())),
    }
}

/// An error reading the file `path` as Python's own
/// `OSError(errno, message, path)`, which picks the subclass of the errno
/// (`FileNotFoundError`, `PermissionError`, `IsADirectoryError`, ...) and
/// sets `.errno` and `.filename`. The errno is the I/O error's; a file
/// too large is `EFBIG`, one not UTF-8 `EILSEQ` (plain `OSError`s), and an
/// I/O error without one `EIO`.
pub fn io_error(py: Python<'_>, e: &TextFileError, message: String, path: &str) -> PyErr {
    let named =
        |name: &str| -> Option<i32> { py.import("errno").ok()?.getattr(name).ok()?.extract().ok() };
    let errno = match e {
        TextFileError::Io(io) => io.raw_os_error().or(match io.kind() {
            std::io::ErrorKind::NotFound => named("ENOENT"),
            std::io::ErrorKind::PermissionDenied => named("EACCES"),
            _ => None,
        }),
        TextFileError::TooLarge { .. } => named("EFBIG"),
        TextFileError::NotUtf8 { .. } => named("EILSEQ"),
    };
    match errno.or_else(|| named("EIO")) {
        Some(n) => PyOSError::new_err((n, message, path.to_string())),
        None => PyOSError::new_err(message),
    }
}

/// Parses and resolves a scene argument.
pub fn read_scene(obj: &Bound<'_, PyAny>) -> PyResult<(fpc::Scene, String)> {
    let (text, shown) = scene_text(obj)?;
    let scene = fpc::Scene::from_toml(&text).map_err(|e| from_scene_read(obj.py(), &e, &shown))?;
    Ok((scene, shown))
}
