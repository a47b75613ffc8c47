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

/// `fpc serve` on a free loopback port, and the address it says.
fn start() -> (Server, String) {
    let mut child = fpc()
        .args(["serve", "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let server = Server(child);
    let mut line = String::new();
    BufReader::new(stdout).read_line(&mut line).unwrap();
    let addr = line
        .split("http://")
        .nth(1)
        .and_then(|r| r.split('/').next())
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();
    assert!(addr.starts_with("127.0.0.1:"), "{line}");
    (server, addr)
}

#[test]
fn serves_the_page_and_the_library_s_finger() {
    let (_server, addr) = start();

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

/// Ctrl-C while a load path far longer than the grace runs: the open
/// connections get 5 s (docs/serve.md), then the computation is stopped,
/// its client answered 503, and the server exits, within a second more.
#[cfg(unix)]
#[test]
fn ctrl_c_answers_a_running_computation_and_exits() {
    let (mut server, addr) = start();
    let slow = r#"{"scene": {"partition": {"elements": 1000}}, "direction": [0, 1], "max_force_n": 100, "max_points": 5000}"#;
    let client = std::thread::spawn(move || request(&addr, "POST /api/load-path", slow));
    std::thread::sleep(std::time::Duration::from_millis(500));
    let pid = server.0.id().to_string();
    let t = std::time::Instant::now();
    let sent = Command::new("kill").args(["-INT", &pid]).status().unwrap();
    assert!(sent.success());
    let answer = client.join().unwrap();
    let answered = t.elapsed();
    assert!(answer.starts_with("HTTP/1.1 503"), "{answer:.300}");
    assert!(answer.contains("shutting down"), "{answer:.300}");
    let status = server.0.wait().unwrap();
    let exited = t.elapsed();
    assert!(status.success(), "{status}");
    assert!(answered.as_secs_f64() > 4.5, "{answered:?}");
    assert!(exited.as_secs_f64() < 6.5, "{exited:?}");
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
