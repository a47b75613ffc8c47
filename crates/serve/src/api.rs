//! The router: the page's files, the JSON API, and the layers around them
//! (a panic becomes a 500, the body's size is bounded). Every computation
//! runs on the blocking pool under a cancellation flag ([`blocking`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use axum::body::Body;
use axum::extract::{DefaultBodyLimit, State};
use axum::http::{HeaderMap, Method, Uri};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post, MethodRouter};
use axum::{Json, Router};
use serde::de::DeserializeOwned;
use serde::Serialize;
use tokio::sync::{watch, Semaphore};
use tower_http::catch_panic::CatchPanicLayer;

use crate::errors::{panic_response, ApiError};
use crate::limits::{read_json, BODY_SECONDS, MAX_BODY_BYTES, WORK_SECONDS};
use crate::{assets, handlers};
use fpc::cancel::panic_text;

/// What the handlers share: how many computations may run at once, and
/// for how long each may run (and wait for its turn).
///
/// Two queues: the quick answers the page asks for while a slider moves
/// (a finger, a grasp) and the slow ones (curves, envelopes, load paths,
/// designs), so that slow requests, however many, never hold up a quick
/// one.
#[derive(Debug, Clone)]
pub struct AppState {
    quick: Arc<Semaphore>,
    slow: Arc<Semaphore>,
    work: Duration,
    body: Duration,
    /// Set once by [`AppState::stop`].
    stopping: Arc<watch::Sender<bool>>,
}

/// Which queue a computation waits in ([`AppState`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Queue {
    /// A finger or a grasp: milliseconds.
    Quick,
    /// Curves, envelopes, load paths and designs: up to seconds.
    Slow,
}

impl AppState {
    /// `workers` computations at once in each queue (at least one; the
    /// others wait their turn, at most `work`), each stopped after `work`;
    /// request bodies must arrive within [`BODY_SECONDS`].
    pub fn new(workers: usize, work: Duration) -> AppState {
        AppState {
            quick: Arc::new(Semaphore::new(workers.max(1))),
            slow: Arc::new(Semaphore::new(workers.max(1))),
            work,
            body: Duration::from_secs(BODY_SECONDS),
            stopping: Arc::new(watch::Sender::new(false)),
        }
    }

    /// Stops every computation of this state, running or waiting for its
    /// turn, and of every request still to come: each request is answered
    /// at once (503, [`ApiError::shutting_down`]) and its computation's
    /// flag set, so that it stops at its next check. The server's last
    /// step after Ctrl-C ([`crate::run`]).
    pub fn stop(&self) {
        self.stopping.send_replace(true);
    }

    /// Completes once [`AppState::stop`] has been called.
    async fn stopped(&self) {
        let mut rx = self.stopping.subscribe();
        // (an error: the sender is gone, which the state itself holds)
        let _ = rx.wait_for(|stopping| *stopping).await;
    }

    /// The same with `body` for a request body to arrive.
    pub fn with_body_time(mut self, body: Duration) -> AppState {
        self.body = body;
        self
    }
}

impl Default for AppState {
    /// The machine's threads at once in each queue, [`WORK_SECONDS`] each.
    fn default() -> AppState {
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
        AppState::new(threads, Duration::from_secs(WORK_SECONDS))
    }
}

/// The application: the page, its files and the API, with the default
/// [`AppState`].
pub fn app() -> Router {
    with_layers(routes(), AppState::default())
}

/// [`app`] as served on `addr`: on a loopback address, a request must name
/// a loopback host (`localhost`, `127.0.0.1`, `[::1]`, any port) in its
/// `Host` header, else 403. A web page of another site whose name an
/// attacker points at 127.0.0.1 (DNS rebinding) names its own host, so it
/// cannot reach the API.
pub fn app_on(addr: std::net::SocketAddr) -> Router {
    app_on_with(addr, AppState::default())
}

/// [`app_on`] with `state`, which the caller keeps to stop the
/// computations ([`AppState::stop`]).
pub fn app_on_with(addr: std::net::SocketAddr, state: AppState) -> Router {
    let app = with_layers(routes(), state);
    if addr.ip().is_loopback() {
        app.layer(axum::middleware::from_fn(loopback_host_only))
    } else {
        app
    }
}

async fn loopback_host_only(request: axum::extract::Request, next: Next) -> Response {
    let host = request
        .headers()
        .get(axum::http::header::HOST)
        .and_then(|h| h.to_str().ok())
        .unwrap_or("");
    if is_loopback_host(host) {
        next.run(request).await
    } else {
        ApiError::forbidden_host(host).into_response()
    }
}

/// Whether a `Host` header names this machine: `localhost`, an IPv4
/// loopback address or `[::1]`, with or without a port.
pub fn is_loopback_host(host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        Some(rest) => rest.split(']').next().unwrap_or(""),
        None => host.rsplit_once(':').map_or(host, |(name, _)| name),
    };
    name.eq_ignore_ascii_case("localhost")
        || name
            .parse::<std::net::IpAddr>()
            .is_ok_and(|ip| ip.is_loopback())
}

/// The routes of the page and the API, before the layers and the state.
pub fn routes() -> Router<AppState> {
    Router::new()
        .route("/", get(assets::index))
        .route("/app.js", get(assets::script))
        .route("/style.css", get(assets::style))
        .route("/api/finger", endpoint(Queue::Quick, handlers::finger))
        .route("/api/grasp", endpoint(Queue::Quick, handlers::grasp))
        .route("/api/lift-curve", endpoint(Queue::Slow, handlers::lift))
        .route("/api/envelope", endpoint(Queue::Slow, handlers::envelope))
        .route("/api/load-path", endpoint(Queue::Slow, handlers::load_path))
        .route("/api/design", endpoint(Queue::Slow, handlers::design))
        .method_not_allowed_fallback(wrong_method)
        .fallback(not_found)
}

/// `routes` with the server's layers (a panic answered with a 500, the
/// body's limit) and `state`. Tests add routes of their own before this.
pub fn with_layers(routes: Router<AppState>, state: AppState) -> Router {
    routes
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .layer(CatchPanicLayer::custom(panic_response))
        .with_state(state)
}

async fn not_found(uri: Uri) -> Response {
    ApiError::not_found(uri.path()).into_response()
}

async fn wrong_method(method: Method, uri: Uri) -> Response {
    ApiError::method_not_allowed(method.as_str(), uri.path()).into_response()
}

/// Sets the flag when dropped: the request ended (answered, timed out, or
/// its client went away), so the computation it started stops.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// Runs `work` on the blocking pool once a permit of `queue` is free
/// (503 after waiting the state's work time), under a cancellation flag
/// ([`fpc::cancel::with_flag`]) that is set when the request ends early
/// (its client disconnects: the handler's future is dropped), its time
/// runs out (503) or the state is stopped ([`AppState::stop`], 503). A
/// panic in `work` is a 500 with its message; the server goes on.
pub async fn blocking<T: Send + 'static>(
    state: &AppState,
    queue: Queue,
    work: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    let permits = match queue {
        Queue::Quick => &state.quick,
        Queue::Slow => &state.slow,
    };
    let turn = tokio::select! {
        turn = tokio::time::timeout(state.work, permits.clone().acquire_owned()) => turn,
        () = state.stopped() => return Err(ApiError::shutting_down()),
    };
    let permit = match turn {
        Err(_) => return Err(ApiError::busy(state.work.as_secs())),
        Ok(Err(_)) => return Err(ApiError::shutting_down()),
        Ok(Ok(permit)) => permit,
    };
    let flag = Arc::new(AtomicBool::new(false));
    let _stop = CancelOnDrop(flag.clone());
    let task = tokio::task::spawn_blocking(move || {
        // the permit is held until the computation has stopped
        let _permit = permit;
        fpc::cancel::with_flag(flag, work)
    });
    let done = tokio::select! {
        done = tokio::time::timeout(state.work, task) => done,
        // (dropping `_stop` sets the flag)
        () = state.stopped() => return Err(ApiError::shutting_down()),
    };
    match done {
        Err(_) => Err(ApiError::timed_out(state.work.as_secs())),
        Ok(Ok(answer)) => answer,
        Ok(Err(e)) if e.is_panic() => Err(ApiError::internal(format!(
            "internal error (a bug, please report it): {}",
            panic_text(e.into_panic().as_ref())
        ))),
        Ok(Err(e)) => Err(ApiError::internal(format!("the computation was lost: {e}"))),
    }
}

/// An API route: the body parsed as `R` and answered with `compute(R)`
/// from the blocking pool, in `queue`, written as JSON.
fn endpoint<R: DeserializeOwned + Send + 'static, T: Serialize + Send + 'static>(
    queue: Queue,
    compute: fn(R) -> Result<T, ApiError>,
) -> MethodRouter<AppState> {
    post(
        move |State(state): State<AppState>, headers: HeaderMap, body: Body| async move {
            let req: R = read_json(&headers, body, state.body).await?;
            blocking(&state, queue, move || compute(req))
                .await
                .map(Json)
        },
    )
}
