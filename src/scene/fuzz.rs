//! The parser and the resolution never panic and always return, on
//! random text and on random edits of the example scenes.

use super::testing::{schema_keys, schema_path, SCENES};
use super::SceneFile;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::sync::mpsc;
use std::time::Duration;

/// Parse and resolve; every error must carry a usable position or a key
/// of the schema.
fn read(text: &str) {
    match SceneFile::parse(text) {
        Ok(f) => match f.resolve() {
            Ok(s) => {
                let _ = s.file().resolve();
            }
            // named by a key of the scene
            Err(e) => assert!(
                schema_keys().contains(&schema_path(&e.field().to_string())),
                "{e}"
            ),
        },
        Err(e) => {
            let lines = text.split('\n').count();
            assert!(e.line >= 1 && e.line <= lines, "{e} in {lines} lines");
            assert!(e.col >= 1, "{e}");
            assert!(!e.message.contains('\n'), "{e}");
        }
    }
}

#[derive(Debug, Clone)]
enum Edit {
    Delete(usize),
    Insert(usize, char),
    Replace(usize, char),
}

fn edit_char() -> impl Strategy<Value = char> {
    prop_oneof![
        4 => prop::sample::select(
            "[]{}=\"'#.,\n -+0123456789eEinfatrusl_".chars().collect::<Vec<_>>()
        ),
        1 => any::<char>(),
    ]
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        any::<usize>().prop_map(Edit::Delete),
        (any::<usize>(), edit_char()).prop_map(|(i, c)| Edit::Insert(i, c)),
        (any::<usize>(), edit_char()).prop_map(|(i, c)| Edit::Replace(i, c)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        match *e {
            Edit::Delete(i) if !chars.is_empty() => {
                let i = i % chars.len();
                chars.remove(i);
            }
            Edit::Insert(i, c) => {
                let i = i % (chars.len() + 1);
                chars.insert(i, c);
            }
            Edit::Replace(i, c) if !chars.is_empty() => {
                let i = i % chars.len();
                chars[i] = c;
            }
            _ => {}
        }
    }
    chars.into_iter().collect()
}

fn runner(cases: u32) -> TestRunner {
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]))
}

/// Runs `f` on another thread and fails if it does not return in time.
fn within(limit: Duration, f: impl FnOnce() + Send + 'static) {
    let (tx, rx) = mpsc::channel();
    let handle = std::thread::spawn(move || {
        f();
        let _ = tx.send(());
    });
    match rx.recv_timeout(limit) {
        Ok(()) => handle.join().unwrap(),
        Err(mpsc::RecvTimeoutError::Disconnected) => {
            if let Err(p) = handle.join() {
                std::panic::resume_unwind(p)
            }
        }
        Err(mpsc::RecvTimeoutError::Timeout) => {
            panic!("the parser did not return within {limit:?}")
        }
    }
}

#[test]
fn random_text_never_panics_or_hangs() {
    within(Duration::from_secs(120), || {
        runner(300)
            .run(&"[ -~\t\n]{0,300}", |text| {
                read(&text);
                Ok(())
            })
            .unwrap();
        // TOML-flavoured text: brackets, keys, values
        let tokenish = prop::collection::vec(
            prop::sample::select(vec![
                "[",
                "]",
                "[[",
                "]]",
                "{",
                "}",
                "=",
                "\"",
                "'",
                "\n",
                ",",
                ".",
                " ",
                "#",
                "actuator",
                "geometry",
                "lx",
                "ribs",
                "list",
                "kind",
                "gripper",
                "grasp",
                "load",
                "fx",
                "1",
                "-2.5e3",
                "nan",
                "inf",
                "true",
                "\"paper\"",
                "\"sphere\"",
                "x0",
                "partition",
                "lengths",
                "elements",
                "\"auto\"",
                "model",
                "name",
                "\"ccm\"",
                "strict",
                "\"\"\"",
                "'''",
            ]),
            0..80,
        )
        .prop_map(|v| v.concat());
        runner(300)
            .run(&tokenish, |text| {
                read(&text);
                Ok(())
            })
            .unwrap();
    });
}

#[test]
fn mutated_examples_never_panic_or_hang() {
    within(Duration::from_secs(120), || {
        let strategy = (0..SCENES.len(), prop::collection::vec(edit(), 1..12));
        runner(400)
            .run(&strategy, |(k, edits)| {
                read(&apply(SCENES[k].1, &edits));
                Ok(())
            })
            .unwrap();
    });
}
