//! Serialization helpers: results are `serde::Serialize`, so JSON (and any
//! other format) comes from derives; these cover the few values that
//! serialize as text or as a record built from methods.

use serde::ser::{SerializeMap, Serializer};

use crate::error::Warning;
use crate::gripper::rules::Invalid;

/// Serializes a value by its `Display` text.
pub(crate) fn display<T: std::fmt::Display, S: Serializer>(v: &T, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(v)
}

impl serde::Serialize for Warning {
    /// `{"kind", "message", "element"?, "value"?, "limit"?}`.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("kind", self.kind())?;
        m.serialize_entry("message", &self.to_string())?;
        if let Some(e) = self.element() {
            m.serialize_entry("element", &e)?;
        }
        if let Some(v) = self.value() {
            m.serialize_entry("value", &v)?;
        }
        if let Some(l) = self.limit() {
            m.serialize_entry("limit", &l)?;
        }
        m.end()
    }
}

impl serde::Serialize for Invalid {
    /// `{"kind", "message"}`.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("kind", self.kind())?;
        m.serialize_entry("message", &self.to_string())?;
        m.end()
    }
}

impl serde::Serialize for crate::model::ModelId {
    /// The model's name (`ccm`, `quad`, ...).
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}
