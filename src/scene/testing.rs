//! Test fixtures shared by the scene's tests: the example scenes,
//! helpers that expect an error, and the walk of the schema.

use std::collections::BTreeSet;
use std::sync::OnceLock;

use serde::de::{
    value, DeserializeSeed, Deserializer, IntoDeserializer, MapAccess, SeqAccess, Visitor,
};
use serde::Deserialize;

use super::{Scene, SceneError, SceneFile, SceneReadError};
use crate::error::InputError;

pub(crate) const SCENES: &[(&str, &str)] = &[
    ("default.toml", include_str!("../../scenes/default.toml")),
    (
        "pressurised.toml",
        include_str!("../../scenes/pressurised.toml"),
    ),
    ("tip_load.toml", include_str!("../../scenes/tip_load.toml")),
    (
        "no_ribs_custom.toml",
        include_str!("../../scenes/no_ribs_custom.toml"),
    ),
    (
        "cuboid_grasp.toml",
        include_str!("../../scenes/cuboid_grasp.toml"),
    ),
    (
        "sphere_grasp.toml",
        include_str!("../../scenes/sphere_grasp.toml"),
    ),
    (
        "shear_tip_load.toml",
        include_str!("../../scenes/shear_tip_load.toml"),
    ),
    ("cl_ribs.toml", include_str!("../../scenes/cl_ribs.toml")),
];

pub(crate) fn input_err(text: &str) -> InputError {
    match Scene::from_toml(text) {
        Err(SceneReadError::Input(e)) => e,
        other => panic!("expected an input error for {text:?}, got {other:?}"),
    }
}

pub(crate) fn syntax_err(text: &str) -> SceneError {
    match SceneFile::parse(text) {
        Err(e) => e,
        Ok(f) => panic!("expected a syntax error for {text:?}, got {f:?}"),
    }
}

/// Every key path of the schema, walked from the serde structs themselves
/// (tables too; a list's entries as `list[]`): `actuator`,
/// `actuator.geometry`, `actuator.geometry.lx`, ..., `partition.lengths[]`,
/// `actuator.ribs.list[].x0`.
pub(crate) fn schema_keys() -> &'static BTreeSet<String> {
    static KEYS: OnceLock<BTreeSet<String>> = OnceLock::new();
    KEYS.get_or_init(|| {
        let mut keys = BTreeSet::new();
        SceneFile::deserialize(Walk {
            path: String::new(),
            keys: &mut keys,
        })
        .expect("the walk fills every field");
        keys
    })
}

/// A key path with its list indexes dropped (`partition.lengths[3]` is
/// `partition.lengths[]`), to look up in [`schema_keys`].
pub(crate) fn schema_path(key: &str) -> String {
    let mut out = String::with_capacity(key.len());
    let mut in_index = false;
    for c in key.chars() {
        match c {
            '[' => {
                in_index = true;
                out.push(c);
            }
            ']' => {
                in_index = false;
                out.push(c);
            }
            _ if in_index => {}
            _ => out.push(c),
        }
    }
    out
}

/// A deserializer that answers every struct with all its fields, every
/// option with `Some`, every list with one entry and every enum with its
/// first variant, recording the path of each field on the way.
struct Walk<'a> {
    path: String,
    keys: &'a mut BTreeSet<String>,
}

impl Walk<'_> {
    fn child(&mut self, name: &str) -> Walk<'_> {
        let path = if self.path.is_empty() {
            name.to_string()
        } else {
            format!("{}.{name}", self.path)
        };
        self.keys.insert(path.clone());
        Walk {
            path,
            keys: self.keys,
        }
    }
}

impl<'de> Deserializer<'de> for Walk<'_> {
    type Error = value::Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Self::Error> {
        // a value that accepts several types (an element count or "auto")
        visitor.visit_u64(1)
    }

    fn deserialize_bool<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Self::Error> {
        visitor.visit_bool(true)
    }

    fn deserialize_u64<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Self::Error> {
        visitor.visit_u64(1)
    }

    fn deserialize_i64<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Self::Error> {
        visitor.visit_i64(1)
    }

    fn deserialize_f64<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Self::Error> {
        visitor.visit_f64(1.0)
    }

    fn deserialize_str<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Self::Error> {
        visitor.visit_str("")
    }

    fn deserialize_string<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Self::Error> {
        visitor.visit_str("")
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Self::Error> {
        visitor.visit_some(self)
    }

    fn deserialize_seq<V: Visitor<'de>>(mut self, visitor: V) -> Result<V::Value, Self::Error> {
        self.path.push_str("[]");
        self.keys.insert(self.path.clone());
        visitor.visit_seq(OneEntry { walk: Some(self) })
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Self::Error> {
        visitor.visit_map(Fields {
            walk: self,
            fields,
            next: 0,
        })
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Self::Error> {
        visitor.visit_enum(IntoDeserializer::<value::Error>::into_deserializer(
            variants[0],
        ))
    }

    serde::forward_to_deserialize_any! {
        i8 i16 i32 i128 u8 u16 u32 u128 f32 char bytes byte_buf unit unit_struct
        newtype_struct tuple tuple_struct map identifier ignored_any
    }
}

struct OneEntry<'a> {
    walk: Option<Walk<'a>>,
}

impl<'de> SeqAccess<'de> for OneEntry<'_> {
    type Error = value::Error;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, Self::Error> {
        match self.walk.take() {
            Some(w) => seed.deserialize(w).map(Some),
            None => Ok(None),
        }
    }
}

struct Fields<'a> {
    walk: Walk<'a>,
    fields: &'static [&'static str],
    next: usize,
}

impl<'de> MapAccess<'de> for Fields<'_> {
    type Error = value::Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Self::Error> {
        match self.fields.get(self.next) {
            Some(&f) => seed
                .deserialize(IntoDeserializer::<value::Error>::into_deserializer(f))
                .map(Some),
            None => Ok(None),
        }
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(
        &mut self,
        seed: V,
    ) -> Result<V::Value, Self::Error> {
        let f = self.fields[self.next];
        self.next += 1;
        seed.deserialize(self.walk.child(f))
    }
}
