//! Scene keys from text, and what each holds: a front end's key argument
//! (`fpc sweep --vary load.fx=...`, a calibration's fitted key) is parsed
//! once into its [`SceneKey`], and everything after works on the typed key.

use std::fmt;
use std::str::FromStr;

use crate::error::InputError;
use crate::field::{
    names, ChannelKey, ClRibKey, Elastic, Field, GeometryKey, Lamina, LaminateKey, PaperRibKey,
    PemcKey, RibKey, ShearLayer,
};

names!(
    /// `[model]`.
    pub ModelKey { Name => "name" }
);
names!(
    /// `[partition]`.
    pub PartitionKey { Elements => "elements", Lengths => "lengths", TipTolMm => "tip_tol_mm" }
);
names!(
    /// `[load]`.
    pub LoadKey { PressureKpa => "pressure_kpa", Kappa => "kappa", Fx => "fx", Fz => "fz" }
);
names!(
    /// `[solve]`.
    pub SolveKey {
        Rtol => "rtol",
        MaxIter => "max_iter",
        Strategy => "strategy",
        SamplesPerElement => "samples_per_element",
        Shape => "shape",
        Stability => "stability",
        Continuation => "continuation",
        MaxStep => "max_step",
    }
);
names!(
    /// `[gripper]` (without its `grasp` table).
    pub GripperKey {
        MountingAngleDeg => "mounting_angle_deg",
        OverlapMm => "overlap_mm",
        PalmMm => "palm_mm",
        Fingers => "fingers",
        Mu => "mu",
        Strict => "strict",
    }
);
names!(
    /// `[gripper.grasp]`.
    pub GraspKey {
        Kind => "kind",
        PressureKpa => "pressure_kpa",
        DMm => "d_mm",
        BetaDeg => "beta_deg",
        FrictionN => "friction_n",
        RMm => "r_mm",
        LiftN => "lift_n",
    }
);

/// A key of a scene file, by its place in the schema. Displays as its
/// TOML path (`actuator.geometry.h1`, `partition.lengths[2]`).
/// [`str::parse`] reads one back from its path (front ends' key
/// arguments, like `fpc sweep --vary`), and [`SceneKey::value`] says what it
/// holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SceneKey {
    Model(ModelKey),
    Geometry(GeometryKey),
    Channel(ChannelKey),
    /// `actuator.ribs` as a whole (ribs that together do not fit).
    Ribs,
    /// `actuator.ribs.kind` (checked by the parser, like every `kind`).
    RibsKind,
    /// `actuator.ribs.list`.
    RibsList,
    /// `actuator.ribs.w1`, `w2`, `t`.
    PaperRib(PaperRibKey),
    /// `actuator.ribs.list[i].<key>`.
    RibEntry(usize, RibKey),
    /// `actuator.cl_ribs` as a whole (too many ribs, or ribs that
    /// together are wider than the strip).
    ClRibs,
    /// `actuator.cl_ribs.list`.
    ClRibsList,
    /// `actuator.cl_ribs.list[i].<key>`.
    ClRibEntry(usize, ClRibKey),
    /// `actuator.<layer>.kind` (checked by the parser).
    MaterialKind(Lamina),
    /// `actuator.<layer>.<key>`.
    Material(Lamina, Elastic),
    Pemc(PemcKey),
    /// `actuator.<layer>.g13`.
    ShearModulus(ShearLayer),
    /// `actuator.laminate.<key>`.
    Laminate(LaminateKey),
    Partition(PartitionKey),
    /// `partition.lengths[i]`.
    PartitionLength(usize),
    Load(LoadKey),
    /// `solve` as a whole (settings that do not fit together).
    SolveTable,
    Solve(SolveKey),
    Gripper(GripperKey),
    Grasp(GraspKey),
    /// `calibration.<key>` (a calibration's record; it changes nothing
    /// that is solved).
    Calibration(&'static str),
}

/// The keys of `[calibration]` (a list's entries at index 0).
pub(crate) const CALIBRATION_KEYS: [&str; 5] = [
    "manifest",
    "parameters[0]",
    "standard_errors[0]",
    "covariance[0][0]",
    "chi_square_per_dof",
];

impl fmt::Display for SceneKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneKey::Model(k) => write!(f, "model.{k}"),
            SceneKey::Geometry(k) => write!(f, "actuator.geometry.{k}"),
            SceneKey::Channel(k) => write!(f, "actuator.channel.{k}"),
            SceneKey::Ribs => f.write_str("actuator.ribs"),
            SceneKey::RibsKind => f.write_str("actuator.ribs.kind"),
            SceneKey::RibsList => f.write_str("actuator.ribs.list"),
            SceneKey::PaperRib(k) => write!(f, "actuator.ribs.{k}"),
            SceneKey::RibEntry(i, k) => write!(f, "actuator.ribs.list[{i}].{k}"),
            SceneKey::ClRibs => f.write_str("actuator.cl_ribs"),
            SceneKey::ClRibsList => f.write_str("actuator.cl_ribs.list"),
            SceneKey::ClRibEntry(i, k) => write!(f, "actuator.cl_ribs.list[{i}].{k}"),
            SceneKey::MaterialKind(l) => write!(f, "actuator.{l}.kind"),
            SceneKey::Material(l, k) => write!(f, "actuator.{l}.{k}"),
            SceneKey::Pemc(k) => write!(f, "actuator.pemc.{k}"),
            SceneKey::ShearModulus(l) => write!(f, "actuator.{l}.g13"),
            SceneKey::Laminate(k) => write!(f, "actuator.laminate.{k}"),
            SceneKey::Partition(k) => write!(f, "partition.{k}"),
            SceneKey::PartitionLength(i) => write!(f, "partition.lengths[{i}]"),
            SceneKey::Load(k) => write!(f, "load.{k}"),
            SceneKey::SolveTable => f.write_str("solve"),
            SceneKey::Solve(k) => write!(f, "solve.{k}"),
            SceneKey::Gripper(k) => write!(f, "gripper.{k}"),
            SceneKey::Grasp(k) => write!(f, "gripper.grasp.{k}"),
            SceneKey::Calibration(k) => write!(f, "calibration.{k}"),
        }
    }
}

macro_rules! into_key {
    ($($leaf:ident => $variant:ident),+ $(,)?) => {
        $(impl From<$leaf> for SceneKey {
            fn from(k: $leaf) -> SceneKey {
                SceneKey::$variant(k)
            }
        })+
    };
}

into_key!(
    ModelKey => Model,
    GeometryKey => Geometry,
    ChannelKey => Channel,
    PaperRibKey => PaperRib,
    PemcKey => Pemc,
    PartitionKey => Partition,
    LoadKey => Load,
    SolveKey => Solve,
    GripperKey => Gripper,
    GraspKey => Grasp,
);

/// What a scene key holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ValueKind {
    /// A number (a float; a whole number is read as one too).
    Number,
    /// A whole number, zero or more (`partition.elements` also takes
    /// `"auto"`).
    WholeNumber,
    /// `true` or `false`.
    Flag,
    /// A name (`model.name`, a `kind`, `solve.strategy`).
    Name,
    /// A list (`partition.lengths`, `actuator.ribs.list`).
    List,
    /// A table of keys (`actuator.ribs`, `solve`).
    Table,
    /// A calibration's record, which changes nothing that is solved.
    Record,
}

impl ValueKind {
    /// Whether a number can be written to a key of this kind.
    pub fn takes_number(self) -> bool {
        matches!(self, ValueKind::Number | ValueKind::WholeNumber)
    }
}

impl fmt::Display for ValueKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ValueKind::Number => "a number",
            ValueKind::WholeNumber => "a whole number",
            ValueKind::Flag => "true or false",
            ValueKind::Name => "a name",
            ValueKind::List => "a list",
            ValueKind::Table => "a table of keys",
            ValueKind::Record => "a calibration's record",
        })
    }
}

impl SceneKey {
    /// Every key of the schema, in its order (list entries at index 0).
    pub fn all() -> Vec<SceneKey> {
        let mut keys: Vec<SceneKey> = Vec::new();
        keys.extend(ModelKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(GeometryKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(ChannelKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend([SceneKey::Ribs, SceneKey::RibsKind, SceneKey::RibsList]);
        keys.extend(PaperRibKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(RibKey::ALL.iter().map(|&k| SceneKey::RibEntry(0, k)));
        keys.extend([SceneKey::ClRibs, SceneKey::ClRibsList]);
        keys.extend(ClRibKey::ALL.iter().map(|&k| SceneKey::ClRibEntry(0, k)));
        for &l in Lamina::ALL {
            keys.push(SceneKey::MaterialKind(l));
            keys.extend(Elastic::ALL.iter().map(|&k| SceneKey::Material(l, k)));
        }
        keys.extend(PemcKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(ShearLayer::ALL.iter().map(|&l| SceneKey::ShearModulus(l)));
        keys.extend(LaminateKey::ALL.iter().map(|&k| SceneKey::Laminate(k)));
        keys.extend(PartitionKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.push(SceneKey::PartitionLength(0));
        keys.extend(LoadKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.push(SceneKey::SolveTable);
        keys.extend(SolveKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(GripperKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(GraspKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(CALIBRATION_KEYS.iter().map(|&k| SceneKey::Calibration(k)));
        keys
    }

    /// What the key holds.
    pub fn value(&self) -> ValueKind {
        use ValueKind::*;
        match *self {
            SceneKey::Model(ModelKey::Name)
            | SceneKey::RibsKind
            | SceneKey::MaterialKind(_)
            | SceneKey::Solve(SolveKey::Strategy)
            | SceneKey::Grasp(GraspKey::Kind) => Name,
            SceneKey::Ribs | SceneKey::ClRibs | SceneKey::SolveTable => Table,
            SceneKey::RibsList
            | SceneKey::ClRibsList
            | SceneKey::Partition(PartitionKey::Lengths) => List,
            SceneKey::Laminate(LaminateKey::PlaneStrain)
            | SceneKey::Solve(SolveKey::Shape | SolveKey::Stability | SolveKey::Continuation)
            | SceneKey::Gripper(GripperKey::Strict) => Flag,
            SceneKey::Partition(PartitionKey::Elements)
            | SceneKey::Solve(SolveKey::MaxIter | SolveKey::SamplesPerElement)
            | SceneKey::Gripper(GripperKey::Fingers) => WholeNumber,
            SceneKey::Calibration(_) => Record,
            SceneKey::Geometry(_)
            | SceneKey::Channel(_)
            | SceneKey::PaperRib(_)
            | SceneKey::RibEntry(..)
            | SceneKey::ClRibEntry(..)
            | SceneKey::Material(..)
            | SceneKey::Pemc(_)
            | SceneKey::ShearModulus(_)
            | SceneKey::Laminate(LaminateKey::ShearCorrection)
            | SceneKey::Partition(PartitionKey::TipTolMm)
            | SceneKey::PartitionLength(_)
            | SceneKey::Load(_)
            | SceneKey::Solve(SolveKey::Rtol | SolveKey::MaxStep)
            | SceneKey::Gripper(
                GripperKey::MountingAngleDeg
                | GripperKey::OverlapMm
                | GripperKey::PalmMm
                | GripperKey::Mu,
            )
            | SceneKey::Grasp(_) => Number,
        }
    }

    /// The key's TOML path, step by step: a table's key, or a list's entry
    /// (`partition.lengths[2]` is `partition`, then `lengths` at 2).
    pub(crate) fn steps(&self) -> Vec<(String, Option<usize>)> {
        self.to_string()
            .split('.')
            .map(|step| match step.split_once('[') {
                Some((name, rest)) => (
                    name.to_string(),
                    rest.trim_end_matches(']').parse::<usize>().ok(),
                ),
                None => (step.to_string(), None),
            })
            .collect()
    }
}

/// The key's path with every list index written as 0, and the indices.
fn shape_of(text: &str) -> Option<(String, Vec<usize>)> {
    let mut shape = String::with_capacity(text.len());
    let mut indices = Vec::new();
    let mut rest = text;
    while let Some(open) = rest.find('[') {
        shape.push_str(&rest[..open]);
        let close = rest[open..].find(']')? + open;
        let digits = &rest[open + 1..close];
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        indices.push(digits.parse().ok()?);
        shape.push_str("[0]");
        rest = &rest[close + 1..];
    }
    shape.push_str(rest);
    Some((shape, indices))
}

/// The edit distance of two short names (insertions, deletions and
/// substitutions of one character): how the front ends find the name
/// nearest to a mistyped one.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diagonal + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

impl FromStr for SceneKey {
    type Err = InputError;

    /// Reads a key from its TOML path (`load.fx`, `actuator.pemc.eps0`,
    /// `partition.lengths[2]`, `actuator.ribs.list[0].x0`). An unknown
    /// path is an error that names the nearest key.
    fn from_str(text: &str) -> Result<SceneKey, InputError> {
        let text = text.trim();
        let all = SceneKey::all();
        let found = shape_of(text).and_then(|(shape, indices)| {
            let key = *all.iter().find(|k| k.to_string() == shape)?;
            match (key, &indices[..]) {
                (SceneKey::PartitionLength(_), &[i]) => Some(SceneKey::PartitionLength(i)),
                (SceneKey::RibEntry(_, k), &[i]) => Some(SceneKey::RibEntry(i, k)),
                (SceneKey::ClRibEntry(_, k), &[i]) => Some(SceneKey::ClRibEntry(i, k)),
                // the calibration's lists are a record, read whole
                (key, _) if shape == text => Some(key),
                _ => None,
            }
        });
        found.ok_or_else(|| {
            // a key whose last step is the one written (`actuator.eps0`
            // for `actuator.pemc.eps0`) before any other near spelling
            let last = |k: &str| -> String {
                let step = k.rsplit('.').next().unwrap_or(k);
                step.split('[').next().unwrap_or(step).to_string()
            };
            let written = last(text);
            let nearest = all
                .iter()
                .map(|k| k.to_string())
                .min_by_key(|k| {
                    (
                        written.is_empty() || last(k) != written,
                        edit_distance(k, text),
                    )
                })
                .unwrap_or_default();
            InputError::Unrecognised {
                field: Field::key("scene key"),
                value: text.to_string(),
                rule: format!("not a key of a scene file (the nearest is `{nearest}`)"),
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneFile;

    #[test]
    fn every_key_reads_back_from_its_path() {
        for key in SceneKey::all() {
            assert_eq!(key.to_string().parse::<SceneKey>().unwrap(), key);
        }
        for key in [
            SceneKey::PartitionLength(12),
            SceneKey::RibEntry(3, RibKey::Width),
        ] {
            assert_eq!(key.to_string().parse::<SceneKey>().unwrap(), key);
        }
        assert_eq!(
            " load.fx ".parse::<SceneKey>().unwrap(),
            SceneKey::Load(LoadKey::Fx)
        );
    }

    #[test]
    fn an_unknown_path_names_the_nearest_key() {
        for (text, nearest) in [
            ("load.fxx", "load.fx"),
            ("actuator.pemc.esp0", "actuator.pemc.eps0"),
            ("gripper.grasp.dmm", "gripper.grasp.d_mm"),
            ("partition.lengths[x]", "partition.lengths[0]"),
            ("load.fx[2]", "load.fx"),
            ("calibration.parameters[3]", "calibration.parameters[0]"),
            ("", "solve"),
            // the last step as written, in another table
            ("actuator.eps0", "actuator.pemc.eps0"),
            ("eps0", "actuator.pemc.eps0"),
            ("fx", "load.fx"),
            ("grasp.d_mm", "gripper.grasp.d_mm"),
        ] {
            let e = text.parse::<SceneKey>().unwrap_err();
            assert!(
                e.to_string()
                    .contains(&format!("the nearest is `{nearest}`")),
                "{text}: {e}"
            );
        }
    }

    #[test]
    fn the_kinds_agree_with_the_schema() {
        // independent of `value`: the serde schema accepts a float, a whole
        // number and a flag exactly where the kind says so
        let lists = "[partition]\nlengths = [50.0, 60.0]\n[actuator.ribs]\nlist = [{ x0 = 1.0, x1 = 2.0, width = 3.0 }]\n[actuator.cl_ribs]\nlist = [{ x0 = 1.0, x1 = 2.0, width = 3.0, height = 0.5 }]\n";
        let accepts = |key: &SceneKey, value: toml::Value| {
            let mut doc: toml::Table = toml::from_str(lists).unwrap();
            let steps = key.steps();
            let mut table = &mut doc;
            for (i, (name, index)) in steps.iter().enumerate() {
                let last = i + 1 == steps.len();
                match (index, last) {
                    (None, true) => {
                        table.insert(name.clone(), value.clone());
                    }
                    (None, false) => {
                        table = table
                            .entry(name.clone())
                            .or_insert_with(|| toml::Value::Table(Default::default()))
                            .as_table_mut()
                            .unwrap();
                    }
                    (Some(k), true) => {
                        table[name.as_str()].as_array_mut().unwrap()[*k] = value.clone();
                    }
                    (Some(k), false) => {
                        table = table[name.as_str()].as_array_mut().unwrap()[*k]
                            .as_table_mut()
                            .unwrap();
                    }
                }
            }
            SceneFile::parse(&toml::to_string(&doc).unwrap()).is_ok()
        };
        for key in SceneKey::all() {
            if matches!(key.value(), ValueKind::Record) {
                continue;
            }
            let float = accepts(&key, toml::Value::Float(1.5));
            let whole = accepts(&key, toml::Value::Integer(3));
            let flag = accepts(&key, toml::Value::Boolean(true));
            let expected = match key.value() {
                ValueKind::Number => (true, true, false),
                ValueKind::WholeNumber => (false, true, false),
                ValueKind::Flag => (false, false, true),
                _ => (false, false, false),
            };
            assert_eq!((float, whole, flag), expected, "{key}: {:?}", key.value());
        }
    }
}
