//! The page's latency budgets, against the server running over loopback
//! (issue 22): a finger or grasp update answers in under 5 ms at the
//! median, and the whole page's recomputation (the finger, the grasp, the
//! lift curve and the sphere envelope, asked at once as the page asks
//! them) in under 100 ms. Each request is a fresh connection, as a slider
//! move's fetch may be; the prestrain changes from request to request so
//! nothing is answered from a previous solve.
//!
//! `cargo bench -p fpc-serve --bench latency [-- ROUNDS]` prints the
//! medians and whether each budget holds (exit status 1 if one does not).

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

const FINGER_BUDGET: Duration = Duration::from_millis(5);
const PAGE_BUDGET: Duration = Duration::from_millis(100);

async fn post(addr: SocketAddr, path: &str, body: Value) -> u16 {
    let body = body.to_string();
    let mut s = TcpStream::connect(addr).await.expect("connect");
    s.set_nodelay(true).expect("nodelay");
    let req = format!(
        "POST {path} HTTP/1.1\r\nHost: bench\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    s.write_all(req.as_bytes()).await.expect("write");
    let mut answer = Vec::new();
    s.read_to_end(&mut answer).await.expect("read");
    let text = String::from_utf8_lossy(&answer);
    text.split(' ')
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0)
}

fn actuator(eps0: f64) -> Value {
    json!({ "actuator": { "pemc": { "eps0": eps0 } }, "partition": { "elements": 8 } })
}

fn loaded_finger(eps0: f64) -> Value {
    let mut s = actuator(eps0);
    s["load"] = json!({ "pressure_kpa": 10 });
    s
}

fn gripper(eps0: f64, grasp: bool) -> Value {
    let mut s = actuator(eps0);
    s["gripper"] = json!({ "mounting_angle_deg": 60, "overlap_mm": 20, "fingers": 3, "mu": 0.6 });
    if grasp {
        s["gripper"]["grasp"] =
            json!({ "kind": "cuboid", "pressure_kpa": 10, "d_mm": 100, "friction_n": 0.3 });
    }
    s
}

fn median(mut t: Vec<Duration>) -> Duration {
    t.sort();
    t[t.len() / 2]
}

fn report(what: &str, t: Duration, budget: Duration) -> bool {
    let ok = t < budget;
    println!(
        "{what:<28} median {:>8.3} ms   budget {:>5} ms   {}",
        t.as_secs_f64() * 1e3,
        budget.as_millis(),
        if ok { "ok" } else { "OVER" }
    );
    ok
}

fn main() {
    // `cargo bench` passes `--bench`; a number is the rounds
    let rounds: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(50)
        .clamp(3, 10_000);
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let ok = rt.block_on(async move {
        let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
        let addr = listener.local_addr().expect("address");
        tokio::spawn(async move { axum::serve(listener, fpc_serve::app()).await });
        let eps0 = |i: usize| 0.2 + 0.05 * (i % 11) as f64 / 10.0;

        let mut finger = Vec::with_capacity(rounds);
        let mut grasp = Vec::with_capacity(rounds);
        for i in 0..rounds {
            let t = Instant::now();
            assert_eq!(
                post(
                    addr,
                    "/api/finger",
                    json!({ "scene": loaded_finger(eps0(i)) })
                )
                .await,
                200
            );
            finger.push(t.elapsed());
            let t = Instant::now();
            assert_eq!(
                post(
                    addr,
                    "/api/grasp",
                    json!({ "scene": gripper(eps0(i), true) })
                )
                .await,
                200
            );
            grasp.push(t.elapsed());
        }
        let mut page = Vec::with_capacity(rounds);
        for i in 0..rounds {
            let e = eps0(i);
            let t = Instant::now();
            let (a, b, c, d) = tokio::join!(
                post(addr, "/api/finger", json!({ "scene": actuator(e) })),
                post(addr, "/api/grasp", json!({ "scene": gripper(e, true) })),
                post(
                    addr,
                    "/api/lift-curve",
                    json!({ "scene": gripper(e, false), "points": 40 })
                ),
                post(
                    addr,
                    "/api/envelope",
                    json!({ "scene": gripper(e, false), "radii": 24, "samples": 24 })
                ),
            );
            page.push(t.elapsed());
            assert_eq!([a, b, c, d], [200; 4]);
        }
        println!("fpc serve over loopback, {rounds} rounds");
        let f = report("finger update", median(finger), FINGER_BUDGET);
        let g = report("grasp update", median(grasp), FINGER_BUDGET);
        let p = report("whole page (4 requests)", median(page), PAGE_BUDGET);
        f && g && p
    });
    if !ok {
        std::process::exit(1);
    }
}
