//! The server over loopback: malformed and hostile input answered with 400
//! naming the field, oversize bodies with 413, failed solves with 422,
//! panics with 500 after which the server still answers; 200 requests at
//! once; clients that leave mid-request. Numbers are checked against the
//! library called directly, never against the server's own answers.

use std::net::SocketAddr;
use std::time::Duration;

use axum::routing::post as route_post;
use fpc::scene::SceneSolution;
use fpc::{Actuator, Load, Plan, PlannedFinger, Scene, SolveOptions};
use fpc_serve::api::{blocking, routes, with_layers, AppState, Queue};
use fpc_serve::ApiError;
use serde_json::{json, Value};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

/// A server on a free loopback port with `app`, running until the test ends.
async fn start(app: axum::Router) -> SocketAddr {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(async move { axum::serve(listener, app).await.unwrap() });
    addr
}

/// A server with the test's extra routes: two that panic, one in the
/// handler and one on the blocking pool.
fn app_with_panics(state: AppState) -> axum::Router {
    let r = routes()
        .route(
            "/test/panic",
            route_post(|| async {
                if std::hint::black_box(true) {
                    panic!("boom in a handler");
                }
                "unreached"
            }),
        )
        .route(
            "/test/panic-blocking",
            route_post(
                |axum::extract::State(s): axum::extract::State<AppState>| async move {
                    blocking(&s, Queue::Quick, || -> Result<Value, ApiError> {
                        if std::hint::black_box(true) {
                            panic!("boom on the blocking pool");
                        }
                        Ok(Value::Null)
                    })
                    .await
                    .map(axum::Json)
                },
            ),
        );
    with_layers(r, state)
}

/// POSTs `body` (raw bytes) and returns the status and the JSON answer.
async fn post_raw(addr: SocketAddr, path: &str, body: &[u8]) -> (u16, Value) {
    let mut s = TcpStream::connect(addr).await.unwrap();
    let head = format!(
        "POST {path} HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    );
    let (mut rd, mut wr) = s.split();
    let write = async {
        // the server may answer (413) and close before the body is all sent
        let _ = wr.write_all(head.as_bytes()).await;
        let _ = wr.write_all(body).await;
    };
    let mut answer = Vec::new();
    let read = rd.read_to_end(&mut answer);
    let ((), got) = tokio::join!(write, read);
    got.unwrap();
    parse(&answer)
}

async fn post(addr: SocketAddr, path: &str, body: Value) -> (u16, Value) {
    post_raw(addr, path, body.to_string().as_bytes()).await
}

fn parse(answer: &[u8]) -> (u16, Value) {
    let text = String::from_utf8_lossy(answer);
    let status: u16 = text
        .split(' ')
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no status line in {text:?}"));
    let body = text.split_once("\r\n\r\n").map_or("", |(_, b)| b);
    let value = serde_json::from_str(body).unwrap_or(Value::String(body.to_string()));
    (status, value)
}

fn assert_error(got: &(u16, Value), status: u16, field: &str) {
    assert_eq!(got.0, status, "{got:?}");
    assert_eq!(got.1["field"], field, "{got:?}");
    assert!(
        got.1["message"].as_str().is_some_and(|m| !m.is_empty()),
        "{got:?}"
    );
}

/// The tip of the paper's finger at `eps0`, N = 8, unloaded: the library
/// called directly.
fn library_tip(eps0: f64) -> [f64; 2] {
    let act = Actuator::paper(eps0).unwrap();
    PlannedFinger::builder(&act)
        .plan(Plan::Equal(8))
        .build()
        .unwrap()
        .solve(&Load::unloaded(), &SolveOptions::default())
        .unwrap()
        .solution
        .tip
}

/// Equal to the last digits JSON keeps (serde_json reads a float back to
/// within an ulp).
fn assert_close(got: [f64; 2], want: [f64; 2]) {
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
    assert!(
        close(got[0], want[0]) && close(got[1], want[1]),
        "{got:?} vs {want:?}"
    );
}

fn finger_body(eps0: f64) -> Value {
    json!({ "scene": { "actuator": { "pemc": { "eps0": eps0 } }, "partition": { "elements": 8 } } })
}

fn tip_of(v: &Value) -> [f64; 2] {
    [
        v["tip_mm"][0].as_f64().unwrap(),
        v["tip_mm"][1].as_f64().unwrap(),
    ]
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn finger_tip_is_the_library_s() {
    let addr = start(fpc_serve::app()).await;
    for eps0 in [0.1, 0.25, 0.4] {
        let (status, v) = post(addr, "/api/finger", finger_body(eps0)).await;
        assert_eq!(status, 200, "{v}");
        let (got, want) = (tip_of(&v), library_tip(eps0));
        assert!(
            (got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9,
            "eps0 {eps0}: {got:?} vs {want:?}"
        );
        assert_eq!(v["kind"], "finger");
        assert!(v["points_mm"].as_array().unwrap().len() > 8);
        assert!(v["validity"].is_boolean());
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_calibrated_scene_answers_with_its_error_bars() {
    let text = "[actuator.pemc]\neps0 = 0.25\n[load]\npressure_kpa = 40.0\n[calibration]\nparameters = [\"actuator.pemc.eps0\", \"load.kappa\"]\ncovariance = [[1e-6, -7.5e-6], [-7.5e-6, 0.000625]]\n";
    let addr = start(fpc_serve::app()).await;
    let (status, v) = post(addr, "/api/finger", json!({ "toml": text })).await;
    assert_eq!(status, 200, "{v}");
    // the library's own propagation of the same scene
    let scene = fpc::Scene::from_toml(text).unwrap();
    let u = scene.uncertainty(&scene.solve().unwrap()).unwrap().unwrap();
    let want = serde_json::to_value(&u).unwrap();
    for (got, want) in v["uncertainty"]["tip_mm"]
        .as_array()
        .unwrap()
        .iter()
        .zip(want["tip_mm"].as_array().unwrap())
    {
        let (g, w) = (got.as_f64().unwrap(), want.as_f64().unwrap());
        assert!(w > 0.0 && (g - w).abs() <= 1e-12 * w, "{g} vs {w}");
    }
    // without the table: no uncertainty
    let plain = text.split("[calibration]").next().unwrap();
    let (_, v) = post(addr, "/api/finger", json!({ "toml": plain })).await;
    assert!(v.get("uncertainty").is_none(), "{v}");
}

/// A gripper whose finger is outside the model at rest (eps0 = 0.6, past
/// the prestrain limit) says so in its envelope, with the library's own
/// findings for that finger; the paper's gripper at rest is valid.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_envelope_says_when_its_finger_is_outside_the_model_at_rest() {
    let addr = start(fpc_serve::app()).await;
    for (text, valid) in [
        (
            "[actuator.pemc]\neps0 = 0.6\n[gripper]\noverlap_mm = 5.0\n",
            false,
        ),
        ("[actuator.pemc]\neps0 = 0.25\n[gripper]\n", true),
    ] {
        let (status, v) = post(addr, "/api/envelope", json!({ "toml": text, "radii": 4 })).await;
        assert_eq!(status, 200, "{v}");
        let Ok(SceneSolution::Gripper { gripper, .. }) = Scene::from_toml(text).unwrap().solve()
        else {
            panic!("a gripper scene")
        };
        let rest = &gripper.reference().warnings;
        assert_eq!(
            !rest.iter().any(fpc::Warning::is_validity),
            valid,
            "{rest:?}"
        );
        assert_eq!(v["rest_valid"], valid, "{v}");
        // the same findings (kind and element; their values to JSON's digits)
        let kinds = |w: &Value| {
            w.as_array()
                .unwrap()
                .iter()
                .map(|f| (f["kind"].to_string(), f["element"].to_string()))
                .collect::<Vec<_>>()
        };
        let want = serde_json::to_value(rest).unwrap();
        assert_eq!(kinds(&v["rest_warnings"]), kinds(&want), "{v}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn grasp_is_the_scene_s() {
    let addr = start(fpc_serve::app()).await;
    let text = "[actuator.pemc]\neps0 = 0.25\n[gripper]\nmounting_angle_deg = 60.0\noverlap_mm = 20.0\n\
                [gripper.grasp]\nkind = \"cuboid\"\npressure_kpa = 20.0\nd_mm = 100.0\nfriction_n = 0.3\n";
    let (status, v) = post(addr, "/api/grasp", json!({ "toml": text })).await;
    assert_eq!(status, 200, "{v}");
    let Ok(SceneSolution::Gripper {
        grasp: Some(want), ..
    }) = Scene::from_toml(text).unwrap().solve()
    else {
        panic!("the scene has a grasp")
    };
    let g = &v["grasp"];
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
    assert!(close(
        g["normal_force_n"].as_f64().unwrap(),
        want.grasp.normal
    ));
    assert!(close(g["height_mm"].as_f64().unwrap(), want.grasp.height));
    assert_eq!(g["valid"].as_bool().unwrap(), want.is_valid());
    assert!(!v["rest_points_gripper_mm"].as_array().unwrap().is_empty());
    // the same scene as JSON keys gives the same grasp
    let scene = json!({
        "actuator": { "pemc": { "eps0": 0.25 } },
        "gripper": { "mounting_angle_deg": 60, "overlap_mm": 20,
                     "grasp": { "kind": "cuboid", "pressure_kpa": 20, "d_mm": 100, "friction_n": 0.3 } }
    });
    let (status, w) = post(addr, "/api/grasp", json!({ "scene": scene })).await;
    assert_eq!(status, 200, "{w}");
    assert_eq!(w["grasp"]["normal_force_n"], g["normal_force_n"]);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_input_is_400_naming_the_field() {
    let addr = start(fpc_serve::app()).await;
    assert_error(
        &post_raw(addr, "/api/finger", b"{\"scene\": ").await,
        400,
        "body",
    );
    assert_error(
        &post_raw(addr, "/api/finger", b"not json").await,
        400,
        "body",
    );
    assert_error(&post_raw(addr, "/api/finger", b"").await, 400, "body");
    assert_error(&post_raw(addr, "/api/finger", b"{} {}").await, 400, "body");
    // nesting deep enough to exhaust a recursive reader's stack
    let deep = format!("{}{}", "[".repeat(100_000), "]".repeat(100_000));
    assert_error(
        &post_raw(addr, "/api/finger", deep.as_bytes()).await,
        400,
        "body",
    );
    let model = json!({ "scene": { "model": { "name": "x".repeat(100_000) } } });
    let long = post(addr, "/api/finger", model).await;
    assert_error(&long, 400, "model.name");
    assert!(long.1["message"].as_str().unwrap().len() < 2000, "{long:?}");
    let nan = b"{\"scene\": {\"actuator\": {\"pemc\": {\"eps0\": NaN}}}}";
    assert_error(&post_raw(addr, "/api/finger", nan).await, 400, "body");
    let huge = b"{\"scene\": {\"actuator\": {\"pemc\": {\"eps0\": 1e400}}}}";
    assert_error(&post_raw(addr, "/api/finger", huge).await, 400, "body");
    let big = json!({ "scene": { "actuator": { "pemc": { "eps0": 1e308 } } } });
    assert_error(
        &post(addr, "/api/finger", big).await,
        400,
        "scene.actuator.pemc.eps0",
    );
    // the same rule in a scene's TOML text, named as its other errors are
    // (`toml`, the key in the message), also in a list and as an integer
    for (text, key) in [
        ("[load]\nfx = 1e308\n", "load.fx = 1e308"),
        ("[load]\nfx = -inf\n", "load.fx = -inf"),
        (
            "[partition]\nlengths = [10.0, 20000000000]\n",
            "partition.lengths[1] = 2e10",
        ),
    ] {
        let got = post(addr, "/api/finger", json!({ "toml": text })).await;
        assert_error(&got, 400, "toml");
        let message = got.1["message"].as_str().unwrap();
        assert!(message.starts_with(key), "{got:?}");
        assert!(message.contains("too large in magnitude"), "{got:?}");
    }
    let neg = json!({ "scene": { "load": { "pressure_kpa": -1e300 } } });
    assert_error(
        &post(addr, "/api/finger", neg).await,
        400,
        "scene.load.pressure_kpa",
    );
    let unknown = json!({ "scene": { "actuator": { "pemc": { "eps1": 0.2 } } } });
    assert_error(
        &post(addr, "/api/finger", unknown).await,
        400,
        "scene.actuator.pemc.eps1",
    );
    assert_error(
        &post(addr, "/api/finger", json!({ "scen": {} })).await,
        400,
        "scen",
    );
    let wrong_type = json!({ "scene": { "load": { "pressure_kpa": "ten" } } });
    assert_error(
        &post(addr, "/api/finger", wrong_type).await,
        400,
        "scene.load.pressure_kpa",
    );
    // the library's own rules, in the scene's keys
    let elements = json!({ "scene": { "partition": { "elements": 100_000_000 } } });
    assert_error(
        &post(addr, "/api/finger", elements).await,
        400,
        "partition.elements",
    );
    let toml = json!({ "toml": "[actuator.pemc]\neps0 = \"x\"\n" });
    assert_error(&post(addr, "/api/finger", toml).await, 400, "toml");
    assert_error(
        &post(addr, "/api/grasp", finger_body(0.25)).await,
        400,
        "gripper",
    );
    // work bounds, before any work
    let gripper = json!({ "gripper": {} });
    let sweep = json!({ "scene": gripper, "points": 10_000_000 });
    assert_error(&post(addr, "/api/lift-curve", sweep).await, 400, "points");
    let radii = json!({ "scene": gripper, "radii": 10_000_000 });
    assert_error(&post(addr, "/api/envelope", radii).await, 400, "radii");
    let samples = json!({ "scene": gripper, "samples": 10_000_000 });
    assert_error(&post(addr, "/api/envelope", samples).await, 400, "samples");
    let starts = json!({ "toml": "fingers = 3\n", "starts": 10_000_000 });
    assert_error(&post(addr, "/api/design", starts).await, 400, "starts");
    let req = json!({ "toml": "fingers = 3\nbogus = 1\n" });
    assert_error(&post(addr, "/api/design", req).await, 400, "toml");
    // a value error is located where the text writes the value
    let req = json!({ "toml": "fingers = 3\n[[object]]\nkind = \"cuboid\"\nsize_mm = [70.0, 100.0]\nlift_n = -1.0\n[vary]\neps0 = [0.1, 0.45]\n" });
    let got = post(addr, "/api/design", req).await;
    assert_error(&got, 400, "object[0].lift_n");
    assert!(
        got.1["message"].as_str().unwrap().starts_with("5:10: "),
        "{got:?}"
    );
    // not a page or an API (docs/serve.md's examples)
    for path in ["/nope", "/api/nothing", "/api/"] {
        assert_error(&post(addr, path, json!({})).await, 404, "path");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_failed_solve_is_422() {
    let addr = start(fpc_serve::app()).await;
    // (a prestrain of 1e5 was the example until the prestrain was
    // bounded: refused input now; one Newton step without continuation
    // cannot meet a tip load)
    let body = json!({ "scene": { "load": { "fx": 1.0 }, "solve": { "max_iter": 1, "continuation": false } } });
    let got = post(addr, "/api/finger", body).await;
    assert_error(&got, 422, "solve");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn oversize_body_is_413() {
    let addr = start(fpc_serve::app()).await;
    let padding = " ".repeat(fpc_serve::limits::MAX_BODY_BYTES + 1);
    let body = format!("{{\"scene\": {{}}{padding}}}");
    assert_error(
        &post_raw(addr, "/api/finger", body.as_bytes()).await,
        413,
        "body",
    );
    // the server still answers
    assert_eq!(post(addr, "/api/finger", finger_body(0.25)).await.0, 200);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_panic_is_500_and_the_server_goes_on() {
    let addr = start(app_with_panics(AppState::default())).await;
    for path in ["/test/panic", "/test/panic-blocking"] {
        let got = post(addr, path, json!({})).await;
        assert_error(&got, 500, "server");
        assert!(
            got.1["message"].as_str().unwrap().contains("boom"),
            "{got:?}"
        );
        let (status, v) = post(addr, "/api/finger", finger_body(0.25)).await;
        assert_eq!(status, 200, "{v}");
        assert_close(tip_of(&v), library_tip(0.25));
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_hundred_requests_at_once() {
    let addr = start(fpc_serve::app()).await;
    let tasks: Vec<_> = (0..200)
        .map(|i| {
            let eps0 = 0.1 + 0.001 * i as f64;
            tokio::spawn(async move { (eps0, post(addr, "/api/finger", finger_body(eps0)).await) })
        })
        .collect();
    for t in tasks {
        let (eps0, (status, v)) = t.await.unwrap();
        assert_eq!(status, 200, "{v}");
        let (got, want) = (tip_of(&v), library_tip(eps0));
        assert!(
            (got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9,
            "eps0 {eps0}: {got:?} vs {want:?}"
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn clients_that_leave_mid_request() {
    // one computation at a time: a request whose client left must give its
    // permit back (its work stopped by the cancellation flag), or the next
    // request would wait for ever
    let addr = start(app_with_panics(AppState::new(1, Duration::from_secs(60)))).await;
    // a body cut off half way
    {
        let mut s = TcpStream::connect(addr).await.unwrap();
        let head = "POST /api/finger HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\nContent-Length: 1000\r\n\r\n{\"scene\":";
        s.write_all(head.as_bytes()).await.unwrap();
    }
    // a long computation whose client goes away after it started
    for _ in 0..3 {
        let mut s = TcpStream::connect(addr).await.unwrap();
        let body = json!({ "scene": { "gripper": {} }, "radii": 200, "samples": 200 }).to_string();
        let head = format!(
            "POST /api/envelope HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
            body.len()
        );
        s.write_all(head.as_bytes()).await.unwrap();
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let answered = tokio::time::timeout(
        Duration::from_secs(30),
        post(addr, "/api/finger", finger_body(0.25)),
    )
    .await
    .expect("the server answers once the leavers' work has stopped");
    assert_eq!(answered.0, 200, "{answered:?}");
    assert_close(tip_of(&answered.1), library_tip(0.25));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_and_its_files() {
    let addr = start(fpc_serve::app()).await;
    for (path, kind, marker) in [
        ("/", "text/html", "<script src=\"/app.js\">"),
        ("/app.js", "text/javascript", "data-tip-x-mm"),
        ("/style.css", "text/css", "svg"),
    ] {
        let mut s = TcpStream::connect(addr).await.unwrap();
        let req = format!("GET {path} HTTP/1.1\r\nHost: test\r\nConnection: close\r\n\r\n");
        s.write_all(req.as_bytes()).await.unwrap();
        let mut answer = String::new();
        s.read_to_string(&mut answer).await.unwrap();
        assert!(answer.starts_with("HTTP/1.1 200"), "{path}: {answer:.200}");
        assert!(answer.to_lowercase().contains(kind), "{path}");
        assert!(answer.contains(marker), "{path}");
        // no network: nothing is fetched from anywhere else
        let outside = answer.replace("http://www.w3.org/2000/svg", "");
        assert!(
            !outside.contains("http://") && !outside.contains("https://"),
            "{path}"
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn lift_curve_points_are_the_scene_s_size_grasps() {
    let addr = start(fpc_serve::app()).await;
    let gripper = json!({ "mounting_angle_deg": 60, "overlap_mm": 20, "mu": 0.6 });
    let body = json!({ "scene": { "gripper": gripper }, "points": 10 });
    let (status, v) = post(addr, "/api/lift-curve", body).await;
    assert_eq!(status, 200, "{v}");
    let points = v["points"].as_array().unwrap();
    assert_eq!(points.len(), 11, "{v}");
    // a point inside the sweep, solved again as a scene's size grasp (f =
    // mu F at grasping angle 0): the same normal force and lift
    let p = &points[5];
    assert_eq!(p["valid"], true, "{p}");
    let d = p["size_mm"].as_f64().unwrap();
    let text = format!(
        "[gripper]\nmounting_angle_deg = 60.0\noverlap_mm = 20.0\nmu = 0.6\n\
         [gripper.grasp]\nkind = \"size\"\npressure_kpa = 0.0\nd_mm = {d}\nbeta_deg = 0.0\n"
    );
    let Ok(SceneSolution::Gripper {
        grasp: Some(want), ..
    }) = Scene::from_toml(&text).unwrap().solve()
    else {
        panic!("the scene has a grasp")
    };
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-12);
    let (f, lift) = (
        p["normal_force_n"].as_f64().unwrap(),
        p["lift_n"].as_f64().unwrap(),
    );
    assert!(
        rel(f, want.grasp.normal) < 1e-6,
        "{f} vs {}",
        want.grasp.normal
    );
    assert!(
        rel(lift, want.grasp.lift) < 1e-6,
        "{lift} vs {}",
        want.grasp.lift
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn design_margins_are_the_library_s() {
    let addr = start(fpc_serve::app()).await;
    // every variable fixed: one design, its margins evaluated
    let text = "fingers = 3\nmu = 0.6\n\n[[object]]\nkind = \"sphere\"\nradius_mm = [40.0, 45.0]\n\
                lift_n = 0.35\n\n[vary]\neps0 = [0.25, 0.25]\nmounting_angle_deg = [60.0, 60.0]\n\
                overlap_mm = [20.0, 20.0]\n";
    let (status, v) = post(addr, "/api/design", json!({ "toml": text, "starts": 0 })).await;
    assert_eq!(status, 200, "{v}");
    let req = fpc::design::Requirements::parse(text).unwrap();
    let want = fpc::design::evaluate(&req, [0.25, 60.0, 20.0]);
    let got = v["worst_margin"].as_f64().unwrap();
    assert!(
        (got - want.worst).abs() <= 1e-9 * want.worst.abs().max(1.0),
        "{got} vs {}",
        want.worst
    );
    assert_eq!(v["feasible"], want.feasible(), "{v}");
    // the design's scene, TOML text, keeps the rule on magnitudes
    let big = json!({ "toml": text, "starts": 0, "scene": "[actuator.pemc]\neps0 = 1e300\n" });
    let got = post(addr, "/api/design", big).await;
    assert_error(&got, 400, "scene");
    assert!(
        got.1["message"]
            .as_str()
            .unwrap()
            .starts_with("actuator.pemc.eps0 = 1e300"),
        "{got:?}"
    );
    assert_eq!(
        v["margins"].as_array().unwrap().len(),
        want.margins.len(),
        "{v}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_design_from_a_scene_is_the_library_s_from_that_finger() {
    let addr = start(fpc_serve::app()).await;
    let text = "[[object]]\nkind = \"cuboid\"\nsize_mm = [80.0, 100.0]\nlift_n = 0.3\n\n\
                [vary]\nmounting_angle_deg = [60.0, 60.0]\noverlap_mm = [20.0, 20.0]\n";
    let scene = "[actuator.cl]\ne = 350.0\n[actuator.pemc]\neps0 = 0.3\n";
    let body = json!({ "toml": text, "starts": 0, "scene": scene });
    let (status, v) = post(addr, "/api/design", body).await;
    assert_eq!(status, 200, "{v}");
    // the design's eps0 is the scene's, and its margins those of a gripper
    // built from the scene's actuator
    assert_eq!(v["design"]["eps0"], 0.3, "{v}");
    let base = fpc::scene::Scene::from_toml(scene).unwrap();
    let req = fpc::design::Requirements::parse(text)
        .unwrap()
        .with_base(fpc::design::DesignBase::from_scene(&base, "test"));
    let want = fpc::design::evaluate(&req, [0.3, 60.0, 20.0]);
    let got = v["worst_margin"].as_f64().unwrap();
    assert!(
        (got - want.worst).abs() <= 1e-9 * want.worst.abs().max(1.0),
        "{got} vs {}",
        want.worst
    );
    let paper = fpc::design::evaluate(
        &fpc::design::Requirements::parse(text).unwrap(),
        [0.3, 60.0, 20.0],
    );
    assert!(
        (got - paper.worst).abs() > 1e-6,
        "the scene made no difference"
    );
    // a scene with an unknown key names the field
    let body = json!({ "toml": text, "starts": 0, "scene": "[actuator.pemc]\neps00 = 0.3\n" });
    assert_error(&post(addr, "/api/design", body).await, 400, "scene");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn envelope_points_are_fresh_searches() {
    let addr = start(fpc_serve::app()).await;
    let body = json!({ "scene": { "gripper": {} }, "radii": 4, "samples": 24 });
    let (status, v) = post(addr, "/api/envelope", body).await;
    assert_eq!(status, 200, "{v}");
    let Ok(SceneSolution::Gripper { gripper, .. }) =
        Scene::from_toml("[gripper]\n").unwrap().solve()
    else {
        panic!("a gripper scene")
    };
    let mut compared = 0;
    for p in v["points"].as_array().unwrap() {
        let r = p["radius_mm"].as_f64().unwrap();
        // the server follows the envelope from radius to radius; here each
        // radius is searched afresh
        let want = gripper.max_sphere_lift(0.0, r, 24).unwrap();
        match (&p["best"], want) {
            (Value::Null, None) => {}
            (best, Some(w)) if !best.is_null() => {
                let got = best["lift_n"].as_f64().unwrap();
                assert!(
                    (got - w.lift).abs() <= 1e-5 * w.lift.abs().max(1e-3),
                    "r = {r}: {got} vs {}",
                    w.lift
                );
                compared += 1;
            }
            (best, w) => panic!("r = {r}: {best} vs {w:?}"),
        }
    }
    assert!(compared >= 2, "{v}");
}

/// A load path's points carry their findings as `fpc` writes them on
/// stderr: each kind's count (`warnings_by_kind`) and every finding of a
/// kind with few, else only the worst. Kept whole (one per element and
/// kind at every point), 5000 points of 1000 elements took most of a
/// gigabyte; summed up, an answer's size is bounded per point.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_load_path_s_findings_are_summed_up_by_kind() {
    let addr = start(fpc_serve::app()).await;
    let body = json!({
        "scene": { "partition": { "elements": 200 } },
        "direction": [0.0, 1.0],
        "max_force_n": 100.0,
        "max_points": 200
    });
    let (status, v) = post(addr, "/api/load-path", body).await;
    assert_eq!(status, 200, "{v}");
    let points = v["points"].as_array().unwrap();
    let mut many = 0;
    for p in points {
        let warnings = p["warnings"].as_array().unwrap();
        let counts = p["warnings_by_kind"].as_object().unwrap();
        let mut listed = 0;
        for (kind, count) in counts {
            let count = count.as_u64().unwrap() as usize;
            let kept = warnings.iter().filter(|w| w["kind"] == kind.as_str());
            let want = if count > fpc::error::WARNINGS_PER_KIND {
                1
            } else {
                count
            };
            assert_eq!(kept.count(), want, "{kind} in {p}");
            many += usize::from(count > fpc::error::WARNINGS_PER_KIND);
            listed += want;
        }
        assert_eq!(warnings.len(), listed, "{p}");
    }
    // (else the path never left the model, and this tests nothing)
    assert!(many > 0, "{v}");
    let bytes = v.to_string().len();
    assert!(
        bytes < 3000 * points.len(),
        "{bytes} bytes for {} points",
        points.len()
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn load_path_ends_at_the_library_s_tip_load() {
    let addr = start(fpc_serve::app()).await;
    let body =
        json!({ "scene": finger_body(0.25)["scene"], "direction": [0.0, 2.0], "max_force_n": 3.0 });
    let (status, v) = post(addr, "/api/load-path", body).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["termination"], "ReachedTarget", "{v}");
    let end = v["points"].as_array().unwrap().last().unwrap().clone();
    assert!(
        (end["force_n"].as_f64().unwrap() - 3.0).abs() < 1e-12,
        "{end}"
    );
    // the same load solved directly (no continuation)
    let act = Actuator::paper(0.25).unwrap();
    let want = PlannedFinger::builder(&act)
        .plan(Plan::Equal(8))
        .build()
        .unwrap()
        .solve(
            &Load::unloaded().with_tip_force(0.0, 3.0),
            &SolveOptions::default(),
        )
        .unwrap()
        .solution
        .tip;
    let got = tip_of(&end);
    assert!(
        (got[0] - want[0]).abs() < 1e-6 && (got[1] - want[1]).abs() < 1e-6,
        "{got:?} vs {want:?}"
    );
    // every point carries the verdict a solve at its load gives: the
    // first (no force) and the last compared with the library's own,
    // solved directly; the path is valid when every point is
    let direct_valid = |force: f64| {
        let s = PlannedFinger::builder(&act)
            .plan(Plan::Equal(8))
            .build()
            .unwrap()
            .solve(
                &Load::unloaded().with_tip_force(0.0, force),
                &SolveOptions::default(),
            )
            .unwrap()
            .solution;
        !s.warnings.iter().any(fpc::Warning::is_validity)
    };
    for max in [3.0, 100.0] {
        let body = json!({ "scene": finger_body(0.25)["scene"], "direction": [0.0, 1.0], "max_force_n": max });
        let (status, v) = post(addr, "/api/load-path", body).await;
        assert_eq!(status, 200, "{v}");
        let points = v["points"].as_array().unwrap();
        let (first, last) = (&points[0], points.last().unwrap());
        assert_eq!(first["valid"], true, "{first}");
        assert_eq!(first["warnings"], json!([]), "{first}");
        let want = direct_valid(last["force_n"].as_f64().unwrap());
        assert_eq!(last["valid"], want, "{last}");
        assert_eq!(last["warnings"] == json!([]), want, "{last}");
        let all = points.iter().all(|p| p["valid"] == true);
        assert_eq!(v["valid"], all, "{v}");
    }
    // 100 N is far past the model's limits
    assert!(!direct_valid(100.0));
    // bounds, before any work
    let zero = json!({ "scene": {}, "direction": [0.0, 0.0], "max_force_n": 1.0 });
    assert_error(&post(addr, "/api/load-path", zero).await, 400, "direction");
    let far = json!({ "scene": {}, "direction": [1.0, 0.0], "max_force_n": 1e6 });
    assert_error(&post(addr, "/api/load-path", far).await, 400, "max_force_n");
    let many = json!({ "scene": {}, "direction": [1.0, 0.0], "max_force_n": 1.0, "max_points": 10_000_000 });
    assert_error(&post(addr, "/api/load-path", many).await, 400, "max_points");
    let auto = json!({ "scene": { "partition": { "elements": "auto" } }, "direction": [1.0, 0.0], "max_force_n": 1.0 });
    assert_error(
        &post(addr, "/api/load-path", auto).await,
        400,
        "partition.elements",
    );
}
