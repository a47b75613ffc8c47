//! What a request may ask for, checked before any work: the body's size
//! and type, how long its client may take to send it, the sizes of
//! sweeps, how many solves run at once and for how long.

use std::time::Duration;

use axum::body::{Body, HttpBody};
use axum::http::{header, HeaderMap};
use http_body_util::{BodyExt, LengthLimitError, Limited};
use serde::de::{DeserializeOwned, Deserializer, Error as _, MapAccess, SeqAccess, Visitor};
use serde_json::Value;

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

/// Seconds a request's computation may run before it is stopped (503);
/// also the longest a request waits for its turn.
pub const WORK_SECONDS: u64 = 60;
/// Seconds a client may take to send a request's headers (from the
/// connection's start, or from the end of its last answer); then the
/// connection is closed.
pub const HEADER_SECONDS: u64 = 10;
/// Seconds a client may take to send a request's body once its headers
/// are in (408).
pub const BODY_SECONDS: u64 = 10;
/// Seconds the open connections get to end after Ctrl-C.
pub const SHUTDOWN_SECONDS: u64 = 5;
/// Seconds, after [`SHUTDOWN_SECONDS`], for the answers of the
/// computations then stopped (503) to be written before the server exits.
pub const STOP_SECONDS: u64 = 1;

/// Reads the body and parses it as JSON into `T`. Refused: a content type
/// other than `application/json` (415: a web page of another site cannot
/// send that type without the server's consent, so it cannot start
/// computations here); a body longer than [`MAX_BODY_BYTES`] (413, at once
/// when its declared length says so); one not in within `time` (408) or
/// malformed on the wire (400). Then a syntax error, a repeated key or a
/// body that is not an object is 400 on `body`; an unknown or missing
/// key, a wrong type or a number out of range is 400 naming the key's
/// path.
pub async fn read_json<T: DeserializeOwned>(
    headers: &HeaderMap,
    body: Body,
    time: Duration,
) -> Result<T, ApiError> {
    let kind = headers
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .unwrap_or("");
    let essence = kind.split(';').next().unwrap_or("").trim();
    if !essence.eq_ignore_ascii_case("application/json") {
        return Err(ApiError::unsupported_type(kind));
    }
    if body.size_hint().lower() > MAX_BODY_BYTES as u64 {
        return Err(ApiError::too_large(MAX_BODY_BYTES));
    }
    let read = tokio::time::timeout(time, Limited::new(body, MAX_BODY_BYTES).collect()).await;
    let bytes = match read {
        Err(_) => return Err(ApiError::body_timed_out(time.as_secs())),
        Ok(Err(e)) if e.is::<LengthLimitError>() => {
            return Err(ApiError::too_large(MAX_BODY_BYTES))
        }
        Ok(Err(e)) => {
            return Err(ApiError::bad(
                "body",
                format!("the request body could not be read: {e}"),
            ))
        }
        Ok(Ok(collected)) => collected.to_bytes(),
    };
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
    let Strict(value) = serde_json::from_slice(bytes)
        .map_err(|e| ApiError::bad("body", format!("the request is not valid JSON: {e}")))?;
    if !value.is_object() {
        return Err(ApiError::bad(
            "body",
            "the request must be a JSON object of named keys",
        ));
    }
    check_magnitudes(&value, &mut String::new(), json_node)?;
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let message = e.into_inner().to_string();
        let field = match named_field(&message) {
            Some(key) if path == "." => key.to_string(),
            Some(key) if !path.ends_with(key) => format!("{path}.{key}"),
            _ if path == "." => "body".to_string(),
            _ => path,
        };
        ApiError::bad(field, format!("not valid for this API: {message}"))
    })
}

/// What [`check_magnitudes`] sees of a value of a parsed document (JSON
/// or TOML).
enum Node<'a, T> {
    Number(f64),
    List(Vec<&'a T>),
    Table(Vec<(&'a str, &'a T)>),
    Other,
}

fn json_node(v: &Value) -> Node<'_, Value> {
    match v {
        // (a JSON number is always an f64 here; none is refused unread)
        Value::Number(n) => Node::Number(n.as_f64().unwrap_or(f64::INFINITY)),
        Value::Array(items) => Node::List(items.iter().collect()),
        Value::Object(map) => Node::Table(map.iter().map(|(k, v)| (k.as_str(), v)).collect()),
        _ => Node::Other,
    }
}

fn toml_node(v: &toml::Value) -> Node<'_, toml::Value> {
    match v {
        // (an integer beyond 2^53 rounds, far past the limit either way)
        toml::Value::Integer(i) => Node::Number(*i as f64),
        toml::Value::Float(x) => Node::Number(*x),
        toml::Value::Array(items) => Node::List(items.iter().collect()),
        toml::Value::Table(map) => Node::Table(map.iter().map(|(k, v)| (k.as_str(), v)).collect()),
        _ => Node::Other,
    }
}

/// Refuses a number beyond [`MAX_MAGNITUDE`] (infinite included; NaN is
/// the library's to refuse) anywhere in `v`, naming its key's path (`path`:
/// where `v` is, as `a.b[2]`); `node` reads a value of the document.
fn check_magnitudes<'a, T>(
    v: &'a T,
    path: &mut String,
    node: fn(&'a T) -> Node<'a, T>,
) -> Result<(), ApiError> {
    let inner = |suffix: &dyn std::fmt::Display, item: &'a T, path: &mut String| {
        let len = path.len();
        path.push_str(&suffix.to_string());
        let checked = check_magnitudes(item, path, node);
        path.truncate(len);
        checked
    };
    match node(v) {
        Node::Number(x) if x.abs() > MAX_MAGNITUDE => {
            let field = if path.is_empty() {
                "body"
            } else {
                path.as_str()
            };
            Err(ApiError::bad(
                field,
                format!("{field} = {x:e}: too large in magnitude (at most {MAX_MAGNITUDE:e} in any unit of the model)"),
            ))
        }
        Node::List(items) => items
            .into_iter()
            .enumerate()
            .try_for_each(|(i, item)| inner(&format_args!("[{i}]"), item, path)),
        Node::Table(entries) => entries.into_iter().try_for_each(|(k, item)| {
            let dot = if path.is_empty() { "" } else { "." };
            inner(&format_args!("{dot}{k}"), item, path)
        }),
        Node::Number(_) | Node::Other => Ok(()),
    }
}

/// The scene file in the TOML text `text` of the request key `field`
/// (`toml`, or `scene` for a design's scene): a syntax error or an
/// unknown key is 400 on `field`, and so is a number beyond
/// [`MAX_MAGNITUDE`], the rule a scene given as JSON keeps, its message
/// naming the scene key (`load.fx = 1e308: too large ...`).
pub fn scene_toml(field: &str, text: &str) -> Result<fpc::scene::SceneFile, ApiError> {
    let file =
        fpc::scene::SceneFile::parse(text).map_err(|e| ApiError::bad(field, e.to_string()))?;
    let table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| ApiError::bad(field, e.to_string()))?;
    check_magnitudes(&toml::Value::Table(table), &mut String::new(), toml_node)
        .map_err(|e| ApiError::bad(field, e.message))?;
    Ok(file)
}

/// The key serde names in "unknown field `key`, expected ..." or
/// "missing field `key`".
fn named_field(message: &str) -> Option<&str> {
    let rest = message
        .strip_prefix("unknown field `")
        .or_else(|| message.strip_prefix("missing field `"))?;
    rest.split('`').next()
}

/// A JSON value read with every object's keys checked for repeats
/// (`serde_json::Value` keeps the last of two, silently).
struct Strict(Value);

impl<'de> serde::Deserialize<'de> for Strict {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Strict, D::Error> {
        d.deserialize_any(StrictVisitor).map(Strict)
    }
}

struct StrictVisitor;

impl<'de> Visitor<'de> for StrictVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(v.into())
    }
    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(v.into())
    }
    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        Ok(v.into())
    }
    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_owned()))
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(Strict(v)) = seq.next_element()? {
            items.push(v);
        }
        Ok(Value::Array(items))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut object = serde_json::Map::new();
        while let Some(key) = map.next_key::<String>()? {
            if object.contains_key(&key) {
                return Err(A::Error::custom(format!("the key `{key}` is given twice")));
            }
            let Strict(v) = map.next_value()?;
            object.insert(key, v);
        }
        Ok(Value::Object(object))
    }
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
