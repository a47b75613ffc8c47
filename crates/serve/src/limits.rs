//! What a request may ask for, checked before any work: the body's size,
//! the sizes of sweeps, how many solves run at once and for how long.

use axum::body::Body;
use serde::de::DeserializeOwned;

use crate::errors::ApiError;

/// The largest request body (bytes): a scene or requirements file is a few
/// hundred bytes; 256 KiB leaves room for long comments.
pub const MAX_BODY_BYTES: usize = 256 * 1024;

/// The most grasping sizes of a lift curve.
pub const MAX_LIFT_POINTS: usize = 400;
/// The most radii of a sphere envelope.
pub const MAX_ENVELOPE_RADII: usize = 200;
/// The most grasping angles a fresh envelope search scans.
pub const MAX_ENVELOPE_SAMPLES: usize = 200;
/// The most points of a load path.
pub const MAX_PATH_POINTS: usize = 5000;
/// The largest tip force a load path follows (N): far past any the
/// paper's fingers carry.
pub const MAX_PATH_FORCE_N: f64 = 100.0;
/// The most random starts of a design.
pub const MAX_DESIGN_STARTS: usize = 16;

/// Seconds a request's computation may run before it is stopped (503).
pub const WORK_SECONDS: u64 = 60;

/// Reads the body (at most [`MAX_BODY_BYTES`]) and parses it as JSON into
/// `T`: a syntax error is 400 on `body`; an unknown key, a wrong type or
/// a number out of range is 400 naming the key's path.
pub async fn read_json<T: DeserializeOwned>(body: Body) -> Result<T, ApiError> {
    let bytes = axum::body::to_bytes(body, MAX_BODY_BYTES)
        .await
        .map_err(|_| ApiError::too_large(MAX_BODY_BYTES))?;
    parse_json(&bytes)
}

/// The largest magnitude of any number in a request: a thousand times
/// the stiffest material in the model's units (MPa, mm, N, kPa). Larger
/// numbers are refused before they reach a solve (1e308 would overflow
/// it).
pub const MAX_MAGNITUDE: f64 = 1e9;

/// Parses `bytes` as JSON into `T` (see [`read_json`]); any number beyond
/// [`MAX_MAGNITUDE`] is refused naming its path.
pub fn parse_json<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, ApiError> {
    let value: serde_json::Value = serde_json::from_slice(bytes)
        .map_err(|e| ApiError::bad("body", format!("the request is not valid JSON: {e}")))?;
    check_magnitudes(&value, &mut String::new())?;
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let message = e.into_inner().to_string();
        let field = match unknown_field(&message) {
            Some(key) if path == "." => key.to_string(),
            Some(key) if !path.ends_with(key) => format!("{path}.{key}"),
            _ if path == "." => "body".to_string(),
            _ => path,
        };
        ApiError::bad(field, format!("not valid for this API: {message}"))
    })
}

/// Refuses a number beyond [`MAX_MAGNITUDE`] anywhere in `v` (`path`: where
/// `v` is, as `a.b[2]`).
fn check_magnitudes(v: &serde_json::Value, path: &mut String) -> Result<(), ApiError> {
    use serde_json::Value;
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.abs() <= MAX_MAGNITUDE => Ok(()),
            _ => {
                let field = if path.is_empty() {
                    "body"
                } else {
                    path.as_str()
                };
                Err(ApiError::bad(
                    field,
                    format!("{field} = {n}: too large in magnitude (at most {MAX_MAGNITUDE:e} in any unit of the model)"),
                ))
            }
        },
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                let len = path.len();
                path.push_str(&format!("[{i}]"));
                check_magnitudes(item, path)?;
                path.truncate(len);
            }
            Ok(())
        }
        Value::Object(map) => {
            for (k, item) in map {
                let len = path.len();
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(k);
                check_magnitudes(item, path)?;
                path.truncate(len);
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

/// The key serde names in "unknown field `key`, expected ...".
fn unknown_field(message: &str) -> Option<&str> {
    let rest = message.strip_prefix("unknown field `")?;
    rest.split('`').next()
}

/// `value` of the request key `field` within `lo..=hi`, else 400.
pub fn count(field: &str, value: usize, lo: usize, hi: usize) -> Result<usize, ApiError> {
    if (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(ApiError::bad(
            field,
            format!("{field} = {value}: must be from {lo} to {hi}"),
        ))
    }
}
