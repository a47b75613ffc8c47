//! The server's limits on how a request arrives, over loopback: its type
//! (JSON only), its method, its size declared or sent, the time its
//! client takes to send headers and body, keys repeated or missing, and
//! the two queues (slow work never holds up a quick answer). Expected
//! statuses and fields come from docs/serve.md, not from the server.

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use fpc_serve::api::{routes, with_layers, AppState};
use serde_json::{json, Value};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

/// A server on a free loopback port: `state`, and `header_time` for the
/// headers, running until the test ends.
async fn start(state: AppState, header_time: Duration) -> SocketAddr {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let app = with_layers(routes(), state);
    tokio::spawn(fpc_serve::serve_on(
        listener,
        app,
        header_time,
        std::future::pending(),
    ));
    addr
}

async fn default_server() -> SocketAddr {
    start(AppState::default(), Duration::from_secs(10)).await
}

/// Sends `raw` as it is and returns the status and JSON of the answer
/// (the server closes or the read ends after `wait`).
async fn exchange(addr: SocketAddr, raw: &[u8], wait: Duration) -> (u16, Value) {
    let mut s = TcpStream::connect(addr).await.unwrap();
    let _ = s.write_all(raw).await;
    let mut answer = Vec::new();
    let _ = tokio::time::timeout(wait, s.read_to_end(&mut answer)).await;
    let text = String::from_utf8_lossy(&answer);
    let status = text
        .split(' ')
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let body = text.split_once("\r\n\r\n").map_or("", |(_, b)| b);
    (status, serde_json::from_str(body).unwrap_or(Value::Null))
}

/// A POST of `body` with `headers` (each ending in CRLF).
fn request(path: &str, headers: &str, body: &str) -> Vec<u8> {
    format!(
        "POST {path} HTTP/1.1\r\nHost: test\r\nConnection: close\r\n{headers}Content-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .into_bytes()
}

const JSON: &str = "Content-Type: application/json\r\n";

fn assert_error(got: &(u16, Value), status: u16, field: &str) {
    assert_eq!(got.0, status, "{got:?}");
    assert_eq!(got.1["field"], field, "{got:?}");
}

const SECOND: Duration = Duration::from_secs(1);

/// A slow request: a load path of 5000 points on 1000 elements, about
/// 30 s in a release build, far longer in a debug one.
fn slow_body() -> String {
    json!({
        "scene": { "partition": { "elements": 1000 } },
        "direction": [0.0, 1.0],
        "max_force_n": 100.0,
        "max_points": 5000
    })
    .to_string()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn only_json_is_read() {
    let addr = default_server().await;
    let body = r#"{"scene":{}}"#;
    for headers in [
        "",
        "Content-Type: text/plain\r\n",
        "Content-Type: application/x-www-form-urlencoded\r\n",
    ] {
        let got = exchange(addr, &request("/api/finger", headers, body), 30 * SECOND).await;
        assert_error(&got, 415, "content-type");
    }
    // parameters and case do not matter
    let got = exchange(
        addr,
        &request(
            "/api/finger",
            "Content-Type: Application/JSON; charset=utf-8\r\n",
            body,
        ),
        30 * SECOND,
    )
    .await;
    assert_eq!(got.0, 200, "{got:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_wrong_method_is_405_with_the_error_shape() {
    let addr = default_server().await;
    let get = b"GET /api/finger HTTP/1.1\r\nHost: test\r\nConnection: close\r\n\r\n";
    assert_error(&exchange(addr, get, 30 * SECOND).await, 405, "method");
    let post = request("/", JSON, "{}");
    assert_error(&exchange(addr, &post, 30 * SECOND).await, 405, "method");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn keys_missing_repeated_or_unnamed() {
    let addr = default_server().await;
    let missing = request("/api/load-path", JSON, r#"{"toml":"","direction":[1,0]}"#);
    assert_error(
        &exchange(addr, &missing, 30 * SECOND).await,
        400,
        "max_force_n",
    );
    let twice = request(
        "/api/finger",
        JSON,
        r#"{"scene":{"actuator":{"pemc":{"eps0":0.1,"eps0":0.3}}}}"#,
    );
    let got = exchange(addr, &twice, 30 * SECOND).await;
    assert_error(&got, 400, "body");
    assert!(
        got.1["message"].as_str().unwrap().contains("eps0"),
        "{got:?}"
    );
    let list = request(
        "/api/finger",
        JSON,
        r#"[null,"[actuator.pemc]\neps0 = 0.3"]"#,
    );
    assert_error(&exchange(addr, &list, 30 * SECOND).await, 400, "body");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_body_too_long_or_broken_is_refused_at_once() {
    let addr = default_server().await;
    // declared far beyond the limit, two bytes sent: refused on the
    // declaration, not after waiting for the rest
    let raw = format!(
        "POST /api/finger HTTP/1.1\r\nHost: test\r\n{JSON}Content-Length: 99999999999\r\n\r\n{{}}"
    );
    let t = Instant::now();
    let got = exchange(addr, raw.as_bytes(), 30 * SECOND).await;
    assert_error(&got, 413, "body");
    assert!(t.elapsed() < 20 * SECOND, "{:?}", t.elapsed());
    // a chunked body whose chunk size is not hexadecimal: malformed, 400
    let raw = format!(
        "POST /api/finger HTTP/1.1\r\nHost: test\r\n{JSON}Transfer-Encoding: chunked\r\n\r\nzz\r\n"
    );
    assert_error(
        &exchange(addr, raw.as_bytes(), 30 * SECOND).await,
        400,
        "body",
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn slow_clients_are_cut_off() {
    let state = AppState::default().with_body_time(SECOND);
    let addr = start(state, SECOND).await;
    // headers never finished, and nothing sent at all: the connection is
    // closed (read_to_end returns) long before the 30 s wait
    for raw in [&b"POST /api/finger HTTP/1.1\r\nHost: x\r\n"[..], &b""[..]] {
        let t = Instant::now();
        let mut s = TcpStream::connect(addr).await.unwrap();
        s.write_all(raw).await.unwrap();
        let mut answer = Vec::new();
        let closed = tokio::time::timeout(30 * SECOND, s.read_to_end(&mut answer)).await;
        assert!(closed.is_ok(), "still open after 30 s");
        assert!(t.elapsed() < 20 * SECOND, "{:?}", t.elapsed());
    }
    // a body that stops half way: 408
    let raw =
        format!("POST /api/finger HTTP/1.1\r\nHost: x\r\n{JSON}Content-Length: 100\r\n\r\n{{\"sc");
    assert_error(
        &exchange(addr, raw.as_bytes(), 30 * SECOND).await,
        408,
        "body",
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn slow_work_does_not_hold_up_a_quick_answer() {
    // one computation at a time in each queue, each up to 60 s
    let addr = start(AppState::new(1, Duration::from_secs(60)), 10 * SECOND).await;
    // its client stays
    let slow = slow_body();
    let mut held = TcpStream::connect(addr).await.unwrap();
    held.write_all(&request("/api/load-path", JSON, &slow))
        .await
        .unwrap();
    tokio::time::sleep(Duration::from_millis(300)).await;
    // a second slow request waits in its queue, not the quick one's
    let quick = json!({ "scene": { "partition": { "elements": 8 } } }).to_string();
    let got = tokio::time::timeout(
        Duration::from_secs(30),
        exchange(addr, &request("/api/finger", JSON, &quick), 30 * SECOND),
    )
    .await
    .expect("a finger is answered while the slow queue is full");
    assert_eq!(got.0, 200, "{got:?}");
    drop(held);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_request_waits_for_its_turn_a_bounded_time() {
    // one slow computation at a time, each stopped after 2 s, and no
    // request waits longer than that for its turn
    let addr = start(AppState::new(1, 2 * SECOND), 10 * SECOND).await;
    let slow = slow_body();
    let first = tokio::spawn(async move {
        exchange(addr, &request("/api/load-path", JSON, &slow), 60 * SECOND).await
    });
    tokio::time::sleep(Duration::from_millis(300)).await;
    let slow = slow_body();
    let t = Instant::now();
    let second = exchange(addr, &request("/api/load-path", JSON, &slow), 60 * SECOND).await;
    // stopped while waiting, or stopped at its own limit after a short
    // turn: 503 either way, well before a full envelope
    assert_error(&second, 503, "server");
    assert!(t.elapsed() < 30 * SECOND, "{:?}", t.elapsed());
    assert_error(&first.await.unwrap(), 503, "server");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stopped_state_answers_every_computation_at_once() {
    // the server's last step after Ctrl-C: a computation running and one
    // waiting for its turn, each allowed 60 s, are answered (503) as soon
    // as the state is stopped, and so is a request that comes later
    let state = AppState::new(1, 60 * SECOND);
    let addr = start(state.clone(), 10 * SECOND).await;
    let slow = || {
        tokio::spawn(async move {
            exchange(
                addr,
                &request("/api/load-path", JSON, &slow_body()),
                60 * SECOND,
            )
            .await
        })
    };
    let running = slow();
    tokio::time::sleep(Duration::from_millis(300)).await;
    let waiting = slow();
    tokio::time::sleep(Duration::from_millis(300)).await;
    let t = Instant::now();
    state.stop();
    assert_error(&running.await.unwrap(), 503, "server");
    assert_error(&waiting.await.unwrap(), 503, "server");
    assert!(t.elapsed() < 5 * SECOND, "{:?}", t.elapsed());
    let quick = json!({ "scene": { "partition": { "elements": 8 } } }).to_string();
    let later = exchange(addr, &request("/api/finger", JSON, &quick), 30 * SECOND).await;
    assert_error(&later, 503, "server");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn on_loopback_only_requests_for_this_machine_are_answered() {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let app = fpc_serve::api::app_on(addr);
    tokio::spawn(fpc_serve::serve_on(
        listener,
        app,
        10 * SECOND,
        std::future::pending(),
    ));
    let page = |host: &str| {
        format!("GET / HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n").into_bytes()
    };
    for host in [
        "evil.example",
        "evil.example:8722",
        "127.0.0.1.evil.example",
    ] {
        let got = exchange(addr, &page(host), 30 * SECOND).await;
        assert_error(&got, 403, "host");
    }
    for host in [
        format!("127.0.0.1:{}", addr.port()),
        format!("localhost:{}", addr.port()),
        "[::1]:8722".to_string(),
        "LOCALHOST".to_string(),
    ] {
        let got = exchange(addr, &page(&host), 30 * SECOND).await;
        assert_eq!(got.0, 200, "{host}: {got:?}");
    }
}
