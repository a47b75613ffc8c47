//! `fpc serve`: it says where it listens, serves the page and the API
//! there (the tip against `fpc finger --json`), and warns about an address
//! other machines can reach.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};

fn fpc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
}

/// Kills the server when the test ends, passed or failed.
struct Server(std::process::Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn request(addr: &str, head: &str, body: &str) -> String {
    let mut s = TcpStream::connect(addr).unwrap();
    write!(
        s,
        "{head} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut answer = String::new();
    s.read_to_string(&mut answer).unwrap();
    answer
}

#[test]
fn serves_the_page_and_the_library_s_finger() {
    let mut child = fpc()
        .args(["serve", "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let _server = Server(child);
    let mut line = String::new();
    BufReader::new(stdout).read_line(&mut line).unwrap();
    let addr = line
        .split("http://")
        .nth(1)
        .and_then(|r| r.split('/').next())
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();
    assert!(addr.starts_with("127.0.0.1:"), "{line}");

    let page = request(&addr, "GET /", "");
    assert!(page.starts_with("HTTP/1.1 200"), "{page:.200}");
    assert!(page.contains("<title>"), "{page:.200}");

    let answer = request(
        &addr,
        "POST /api/finger",
        r#"{"scene": {"actuator": {"pemc": {"eps0": 0.3}}}}"#,
    );
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer:.300}");
    let body: serde_json::Value =
        serde_json::from_str(answer.split_once("\r\n\r\n").unwrap().1).unwrap();
    let out = fpc()
        .args(["finger", "--eps0", "0.3", "--json"])
        .output()
        .unwrap();
    let want: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for i in 0..2 {
        let (g, w) = (
            body["tip_mm"][i].as_f64().unwrap(),
            want["tip_mm"][i].as_f64().unwrap(),
        );
        assert!((g - w).abs() <= 1e-12 * w.abs().max(1.0), "{g} vs {w}");
    }
}

#[test]
fn warns_about_a_non_loopback_address() {
    // an address of the documentation range, never this machine's: the
    // warning comes before the bind fails, and nothing is exposed
    let out = fpc()
        .args(["serve", "--bind", "192.0.2.1", "--port", "0"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not a loopback address"), "{err}");
    assert!(err.contains("cannot serve on 192.0.2.1"), "{err}");
    assert!(!out.status.success());
}
