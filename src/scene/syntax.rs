//! The syntax of scene-like TOML documents (scenes, requirements files,
//! measurement manifests): a parse error as [`SceneError`] with its line,
//! column and, where the text shows it, the dotted key it belongs to; and
//! the way back, the line and column of a dotted key ([`locate`]).

/// A scene document that is not valid TOML, or has an unknown key or a
/// value of the wrong type. `line` and `col` (both from 1; the column
/// counts characters) locate the offending text.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{line}:{col}: {message}")]
pub struct SceneError {
    /// Line of the offending text (from 1).
    pub line: usize,
    /// Column of the offending text (from 1, in characters).
    pub col: usize,
    /// What is wrong and, where the parser knows, what was expected (one line).
    pub message: String,
}

impl SceneError {
    pub(crate) fn from_toml(text: &str, e: &toml::de::Error) -> SceneError {
        let (line, col) = match e.span() {
            Some(span) => line_col(text, span.start),
            None => (1, 1),
        };
        let mut message = e
            .message()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join("; ");
        if e.span().is_none() {
            message.push_str(" (position unknown)");
        }
        // a wrong type or a key written twice: the key, as the user wrote
        // it, before the parser's words (which name only the type)
        if let Some(key) = e.span().and_then(|span| key_at(text, span.start)) {
            if !message.contains(&key) {
                message = format!("{key}: {message}");
            }
        }
        SceneError { line, col, message }
    }
}

/// The dotted path of the key the text at byte `offset` belongs to, read
/// from the lines up to it: the last table header (array tables indexed
/// from 0, as `specimen[1].test[0]`) and the key on the offset's line, or
/// the header itself when the offset is on one. `None` where that line
/// has no plain `key =` (a continuation line of an array, a quoted key):
/// the message then keeps the line and column alone.
pub(crate) fn key_at(text: &str, offset: usize) -> Option<String> {
    let mut o = offset.min(text.len());
    while !text.is_char_boundary(o) {
        o -= 1;
    }
    let start = text[..o].rfind('\n').map_or(0, |i| i + 1);
    let end = text[o..].find('\n').map_or(text.len(), |i| o + i);
    // array tables seen so far, with their counts (a new parent entry
    // restarts its children's)
    let mut counts: Vec<(String, usize)> = Vec::new();
    let mut table = String::new();
    let read = |line: &str, counts: &mut Vec<(String, usize)>| -> Option<String> {
        let (path, array) = header(line)?;
        if array {
            counts.retain(|(p, _)| !p.starts_with(&format!("{path}.")));
            match counts.iter_mut().find(|(p, _)| *p == path) {
                Some((_, n)) => *n += 1,
                None => counts.push((path.clone(), 1)),
            }
        }
        Some(indexed(&path, counts))
    };
    for l in text[..start].lines() {
        if let Some(t) = read(l, &mut counts) {
            table = t;
        }
    }
    let line = &text[start..end];
    if let Some(t) = read(line, &mut counts) {
        return Some(t);
    }
    let (key, _) = line.split_once('=')?;
    let key = dotted(key)?;
    Some(if table.is_empty() {
        key
    } else {
        format!("{table}.{key}")
    })
}

/// A table header's dotted path and whether it is an array table
/// (`[[...]]`); `None` for any other line.
fn header(line: &str) -> Option<(String, bool)> {
    let l = line.trim();
    let (inner, array) = match l.strip_prefix("[[") {
        Some(r) => (r.split_once("]]")?.0, true),
        None => (l.strip_prefix('[')?.split_once(']')?.0, false),
    };
    Some((dotted(inner)?, array))
}

/// A bare dotted key (`a.b_c`), spaces around the dots dropped; `None`
/// for anything else (quoted keys, numbers first, values).
fn dotted(key: &str) -> Option<String> {
    let parts: Vec<&str> = key.split('.').map(str::trim).collect();
    let bare = |p: &&str| {
        p.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
            && p.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    };
    parts.iter().all(bare).then(|| parts.join("."))
}

/// `path` with the index of every array table along it (`specimen.test`
/// to `specimen[0].test[2]`).
fn indexed(path: &str, counts: &[(String, usize)]) -> String {
    let mut out = String::new();
    let mut prefix = String::new();
    for part in path.split('.') {
        if !prefix.is_empty() {
            prefix.push('.');
            out.push('.');
        }
        prefix.push_str(part);
        out.push_str(part);
        if let Some((_, n)) = counts.iter().find(|(p, _)| *p == prefix) {
            out.push_str(&format!("[{}]", n - 1));
        }
    }
    out
}

/// Line and column (both from 1; the column in characters) of a byte
/// offset into `text`. An offset past the end is the end; one inside a
/// character is that character.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut o = offset.min(text.len());
    while !text.is_char_boundary(o) {
        o -= 1;
    }
    let before = &text[..o];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[start..].chars().count() + 1)
}

/// Line and column of the value at `path` (`vary.eps0`,
/// `object[1].size_mm[0]`: keys separated by dots, each followed by any
/// array indices) in the TOML document `text`; `None` if it is not there.
pub fn locate(text: &str, path: &str) -> Option<(usize, usize)> {
    let doc = toml::de::DeTable::parse(text).ok()?;
    let root = toml::de::DeValue::Table(doc.into_inner());
    let mut at: (&toml::de::DeValue<'_>, Option<std::ops::Range<usize>>) = (&root, None);
    for segment in path.split('.') {
        let mut parts = segment.split('[');
        let v = at.0.get(parts.next()?)?;
        at = (v.get_ref(), Some(v.span()));
        for index in parts {
            let i: usize = index.strip_suffix(']')?.parse().ok()?;
            let v = at.0.get(i)?;
            at = (v.get_ref(), Some(v.span()));
        }
    }
    at.1.map(|span| line_col(text, span.start))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testing::syntax_err;

    /// A value of the wrong type, or a key written twice: the parser
    /// names only the type or "duplicate key"; the message names the key.
    #[test]
    fn a_wrong_type_or_a_second_key_names_the_key() {
        for (text, key, (line, says)) in [
            ("[load]\nfx = \"0.5\"\n", "load.fx", (2, "invalid type")),
            (
                "[actuator.geometry]\nlx = 100\nlx = 90\n",
                "actuator.geometry.lx",
                (3, "duplicate key"),
            ),
            ("[actuator.ribs]\nkind = 0\n", "actuator.ribs.kind", (2, "")),
            ("[solve]\nmax_iter = -3\n", "solve.max_iter", (2, "")),
        ] {
            let e = syntax_err(text);
            assert_eq!(e.line, line, "{e}");
            assert!(e.message.starts_with(&format!("{key}: ")), "{text:?}: {e}");
            assert!(e.message.contains(says), "{e}");
        }
    }

    #[test]
    fn the_key_at_an_offset_is_read_from_the_headers_above_it() {
        let text = "top = 1\n[[specimen]]\nname = 'a'\n[[specimen.test]]\nkind = 1\n\
                    [[specimen]]\n[specimen.own]\n  e2 . x = 3\n[[specimen.test]]\nfile = 2\n\
                    list = [\n  1,\n]\n";
        let at = |needle: &str| key_at(text, text.find(needle).unwrap());
        assert_eq!(at("top").as_deref(), Some("top"));
        assert_eq!(at("name").as_deref(), Some("specimen[0].name"));
        assert_eq!(at("kind").as_deref(), Some("specimen[0].test[0].kind"));
        assert_eq!(at("e2").as_deref(), Some("specimen[1].own.e2.x"));
        assert_eq!(at("file").as_deref(), Some("specimen[1].test[0].file"));
        assert_eq!(at("[specimen.own]").as_deref(), Some("specimen[1].own"));
        // a continuation line of an array: no key of its own
        assert_eq!(at("  1,"), None);
        // a quoted key is not guessed at
        assert_eq!(key_at("[a]\n\"b c\" = 1\n", 5), None);
    }

    #[test]
    fn unknown_key_is_rejected_with_its_name_and_line() {
        let e = syntax_err("[actuator.geometry]\nlx = 100\nlxx = 3\n");
        assert_eq!(e.line, 3, "{e}");
        assert_eq!(e.col, 1, "{e}");
        assert!(e.message.contains("lxx"), "{e}");
        let e = syntax_err("[load]\npresure_kpa = 3\n");
        assert_eq!((e.line, e.col), (2, 1), "{e}");
        assert!(e.message.contains("presure_kpa"), "{e}");
        // a misspelled section
        let e = syntax_err("# comment\n\n[actuatr]\n");
        assert_eq!(e.line, 3, "{e}");
        assert!(e.message.contains("actuatr"), "{e}");
        // a misspelled key inside an inline table in a list
        let e = syntax_err("[actuator.ribs]\nlist = [\n  { x0 = 0, x1 = 5, widht = 2 },\n]\n");
        assert_eq!(e.line, 3, "{e}");
        assert!(e.message.contains("widht"), "{e}");
        // a rib as an array of the wrong length, and a key missing
        for (list, found) in [("[10, 20, 2, 99]", "4"), ("[10, 20]", "2")] {
            let e = syntax_err(&format!("[actuator.ribs]\nlist = [\n  {list},\n]\n"));
            assert_eq!((e.line, e.col), (3, 3), "{e}");
            assert!(e.message.contains(&format!("has {found} number(s)")), "{e}");
        }
        let e = syntax_err("[actuator.ribs]\nlist = [{ x0 = 0, x1 = 5 }]\n");
        assert!(e.message.contains("width"), "{e}");
        // a bad enumeration value
        let e = syntax_err("[gripper.grasp]\nkind = \"cube\"\n");
        assert_eq!(e.line, 2, "{e}");
        assert!(e.message.contains("cube"), "{e}");
    }

    #[test]
    fn syntax_errors_give_line_and_column() {
        let e = syntax_err("[load]\nfx = 0.1\nfz = = 2\n");
        assert_eq!(e.line, 3, "{e}");
        assert_eq!(e.col, 6, "{e}");
        let e = syntax_err("[partition]\nelements = 8.5\n");
        assert_eq!(e.line, 2, "{e}");
        assert_eq!(e.col, 12, "{e}");
        assert!(e.to_string().starts_with("2:12: "), "{e}");
        let e = syntax_err("[solve\n");
        assert_eq!(e.line, 1, "{e}");
        let e = syntax_err("[load]\nfx = \"a\"\n");
        assert_eq!((e.line, e.col), (2, 6), "{e}");
        let e = syntax_err("[partition]\nelements = -1\n");
        assert_eq!((e.line, e.col), (2, 12), "{e}");
        // columns count characters, not bytes
        let e = syntax_err("# é\n[load] # ü\nfx = ä\n");
        assert_eq!((e.line, e.col), (3, 6), "{e}");
        // messages are one line
        for text in [
            "[a",
            "x = [1,",
            "a = \"\n\"",
            "[[gripper]]",
            "a.b = 1\na = 2",
        ] {
            let e = syntax_err(text);
            assert!(!e.message.contains('\n'), "{e}");
        }
    }

    #[test]
    fn line_col_of_offsets() {
        let t = "ab\ncé\n";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 2), (1, 3));
        assert_eq!(line_col(t, 3), (2, 1));
        assert_eq!(line_col(t, 4), (2, 2));
        assert_eq!(line_col(t, 5), (2, 2)); // inside é
        assert_eq!(line_col(t, 6), (2, 3));
        assert_eq!(line_col(t, 7), (3, 1));
        assert_eq!(line_col(t, 100), (3, 1));
    }
}
