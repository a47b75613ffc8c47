//! The router: the page's files, the JSON API, and the layers around them
//! (a panic becomes a 500, the body's size is bounded). Every computation
//! runs on the blocking pool under a cancellation flag ([`blocking`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use axum::body::Body;
use axum::extract::{DefaultBodyLimit, State};
use axum::http::Uri;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde::de::DeserializeOwned;
use serde_json::Value;
use tokio::sync::Semaphore;
use tower_http::catch_panic::CatchPanicLayer;

use crate::errors::{panic_response, ApiError};
use crate::limits::{read_json, MAX_BODY_BYTES, WORK_SECONDS};
use crate::{assets, handlers};
use fpc::cancel::panic_text;

/// What the handlers share: how many computations may run at once, and
/// for how long each may run.
#[derive(Debug, Clone)]
pub struct AppState {
    permits: Arc<Semaphore>,
    work: Duration,
}

impl AppState {
    /// `workers` computations at once (at least one; the others wait their
    /// turn), each stopped after `work`.
    pub fn new(workers: usize, work: Duration) -> AppState {
        AppState {
            permits: Arc::new(Semaphore::new(workers.max(1))),
            work,
        }
    }
}

impl Default for AppState {
    /// Twice the machine's threads at once, [`WORK_SECONDS`] each.
    fn default() -> AppState {
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
        AppState::new(2 * threads, Duration::from_secs(WORK_SECONDS))
    }
}

/// The application: the page, its files and the API, with the default
/// [`AppState`].
pub fn app() -> Router {
    with_layers(routes(), AppState::default())
}

/// The routes of the page and the API, before the layers and the state.
pub fn routes() -> Router<AppState> {
    Router::new()
        .route("/", get(assets::index))
        .route("/app.js", get(assets::script))
        .route("/style.css", get(assets::style))
        .route("/api/finger", post(finger))
        .route("/api/grasp", post(grasp))
        .route("/api/lift-curve", post(lift_curve))
        .route("/api/envelope", post(envelope))
        .route("/api/load-path", post(load_path))
        .route("/api/design", post(design))
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

/// Sets the flag when dropped: the request ended (answered, timed out, or
/// its client went away), so the computation it started stops.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// Runs `work` on the blocking pool once a permit is free, under a
/// cancellation flag ([`fpc::cancel::with_flag`]) that is set when the
/// request ends early (its client disconnects: the handler's future is
/// dropped) or its time runs out (503). A panic in `work` is a 500 with
/// its message; the server goes on.
pub async fn blocking<T: Send + 'static>(
    state: &AppState,
    work: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    let permit = state
        .permits
        .clone()
        .acquire_owned()
        .await
        .map_err(|_| ApiError::internal("the server is shutting down"))?;
    let flag = Arc::new(AtomicBool::new(false));
    let _stop = CancelOnDrop(flag.clone());
    let task = tokio::task::spawn_blocking(move || {
        // the permit is held until the computation has stopped
        let _permit = permit;
        fpc::cancel::with_flag(flag, work)
    });
    match tokio::time::timeout(state.work, task).await {
        Err(_) => Err(ApiError::timed_out(state.work.as_secs())),
        Ok(Ok(answer)) => answer,
        Ok(Err(e)) if e.is_panic() => Err(ApiError::internal(format!(
            "internal error (a bug, please report it): {}",
            panic_text(e.into_panic().as_ref())
        ))),
        Ok(Err(e)) => Err(ApiError::internal(format!("the computation was lost: {e}"))),
    }
}

/// Parses the body as `R` and answers `compute(R)` from the blocking pool.
async fn answer<R: DeserializeOwned + Send + 'static>(
    state: &AppState,
    body: Body,
    compute: fn(R) -> Result<Value, ApiError>,
) -> Result<Json<Value>, ApiError> {
    let req: R = read_json(body).await?;
    blocking(state, move || compute(req)).await.map(Json)
}

async fn finger(State(s): State<AppState>, body: Body) -> Result<Json<Value>, ApiError> {
    answer(&s, body, handlers::finger).await
}

async fn grasp(State(s): State<AppState>, body: Body) -> Result<Json<Value>, ApiError> {
    answer(&s, body, handlers::grasp).await
}

async fn lift_curve(State(s): State<AppState>, body: Body) -> Result<Json<Value>, ApiError> {
    answer(&s, body, handlers::lift).await
}

async fn envelope(State(s): State<AppState>, body: Body) -> Result<Json<Value>, ApiError> {
    answer(&s, body, handlers::envelope).await
}

async fn load_path(State(s): State<AppState>, body: Body) -> Result<Json<Value>, ApiError> {
    answer(&s, body, handlers::load_path).await
}

async fn design(State(s): State<AppState>, body: Body) -> Result<Json<Value>, ApiError> {
    answer(&s, body, handlers::design).await
}
