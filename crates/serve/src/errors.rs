//! The API's errors: one JSON shape, `{"field", "message"}`, with the
//! status saying whose fault it is (400 the input, 403 a request for
//! another host, 404 a path the server does not know, 405 the method,
//! 408 a body that did not arrive in time, 413 the body's size, 415 a
//! body not sent as JSON, 422 a solve that failed on valid input, 503
//! work stopped at its time limit, at a shutdown, or a request that
//! waited too long for its turn, 500 a fault of the server, never caused
//! by input alone).

use std::any::Any;

use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use fpc::{InputError, SolveError};

/// An error answer of the API.
#[derive(Debug, Clone, PartialEq)]
pub struct ApiError {
    /// The HTTP status.
    pub status: StatusCode,
    /// The field at fault: a scene key (`actuator.pemc.eps0`), a request
    /// key (`points`), `body` for the request as a whole, or `server`.
    pub field: String,
    /// What is wrong, in words.
    pub message: String,
}

impl ApiError {
    /// 400: the input is wrong.
    pub fn bad(field: impl Into<String>, message: impl Into<String>) -> ApiError {
        ApiError {
            status: StatusCode::BAD_REQUEST,
            field: field.into(),
            message: message.into(),
        }
    }

    /// 422: valid input whose solve failed.
    pub fn unsolved(field: impl Into<String>, message: impl Into<String>) -> ApiError {
        ApiError {
            status: StatusCode::UNPROCESSABLE_ENTITY,
            field: field.into(),
            message: message.into(),
        }
    }

    /// 413: the body is larger than the limit.
    pub fn too_large(limit: usize) -> ApiError {
        ApiError {
            status: StatusCode::PAYLOAD_TOO_LARGE,
            field: "body".into(),
            message: format!("the request body is larger than {limit} bytes, the limit"),
        }
    }

    /// 503: the work took longer than its limit and was stopped.
    pub fn timed_out(seconds: u64) -> ApiError {
        ApiError {
            status: StatusCode::SERVICE_UNAVAILABLE,
            field: "server".into(),
            message: format!("the computation took longer than {seconds} s and was stopped"),
        }
    }

    /// 415: the body is not declared as JSON.
    pub fn unsupported_type(given: &str) -> ApiError {
        let given = if given.is_empty() { "none" } else { given };
        ApiError {
            status: StatusCode::UNSUPPORTED_MEDIA_TYPE,
            field: "content-type".into(),
            message: format!(
                "the API reads JSON: send the header `Content-Type: application/json` (given: {given})"
            ),
        }
    }

    /// 408: the client took longer than the limit to send the body.
    pub fn body_timed_out(seconds: u64) -> ApiError {
        ApiError {
            status: StatusCode::REQUEST_TIMEOUT,
            field: "body".into(),
            message: format!("the request body did not arrive within {seconds} s"),
        }
    }

    /// 503: the request waited longer than the limit for its turn.
    pub fn busy(seconds: u64) -> ApiError {
        ApiError {
            status: StatusCode::SERVICE_UNAVAILABLE,
            field: "server".into(),
            message: format!(
                "the server is busy: the request waited {seconds} s for its turn; try again"
            ),
        }
    }

    /// 503: the server is shutting down (Ctrl-C) and stopped the
    /// computation, running or waiting for its turn.
    pub fn shutting_down() -> ApiError {
        ApiError {
            status: StatusCode::SERVICE_UNAVAILABLE,
            field: "server".into(),
            message: "the server is shutting down: the computation was stopped".into(),
        }
    }

    /// 403: a request naming another host than this machine's.
    pub fn forbidden_host(host: &str) -> ApiError {
        ApiError {
            status: StatusCode::FORBIDDEN,
            field: "host".into(),
            message: format!(
                "the server listens on a loopback address and answers requests for localhost only (Host: {host})"
            ),
        }
    }

    /// 405: the path exists, the method does not.
    pub fn method_not_allowed(method: &str, path: &str) -> ApiError {
        ApiError {
            status: StatusCode::METHOD_NOT_ALLOWED,
            field: "method".into(),
            message: format!("{path} does not take {method} (the API takes POST, the page GET)"),
        }
    }

    /// 500: a fault of the server (a panic), with what it said.
    pub fn internal(message: impl Into<String>) -> ApiError {
        ApiError {
            status: StatusCode::INTERNAL_SERVER_ERROR,
            field: "server".into(),
            message: message.into(),
        }
    }

    /// 404 for a path the server does not know.
    pub fn not_found(path: &str) -> ApiError {
        ApiError {
            status: StatusCode::NOT_FOUND,
            field: "path".into(),
            message: format!("no page or API at {path}"),
        }
    }

    /// The JSON body, `{"field": ..., "message": ...}`, each cut to
    /// [`MAX_ERROR_CHARS`] characters (a message may quote a long value).
    pub fn body(&self) -> serde_json::Value {
        serde_json::json!({ "field": cut(&self.field), "message": cut(&self.message) })
    }
}

/// The longest field or message an error answer carries (characters).
pub const MAX_ERROR_CHARS: usize = 1000;

fn cut(s: &str) -> String {
    match s.char_indices().nth(MAX_ERROR_CHARS) {
        Some((at, _)) => format!("{}... (cut)", &s[..at]),
        None => s.to_string(),
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (
            self.status,
            [(header::CONTENT_TYPE, "application/json")],
            self.body().to_string(),
        )
            .into_response()
    }
}

impl From<InputError> for ApiError {
    /// 400 naming the field as a scene file does.
    fn from(e: InputError) -> ApiError {
        let e = fpc::scene::scene_input(e);
        ApiError::bad(e.field().to_string(), e.to_string())
    }
}

impl From<SolveError> for ApiError {
    /// An input error inside a solve is 400; any other failure 422.
    fn from(e: SolveError) -> ApiError {
        match fpc::scene::scene_solve(e) {
            SolveError::Input(i) => i.into(),
            SolveError::Cancelled => ApiError::unsolved("solve", "the solve was stopped"),
            other => ApiError::unsolved("solve", other.to_string()),
        }
    }
}

impl From<fpc::scene::SceneReadError> for ApiError {
    fn from(e: fpc::scene::SceneReadError) -> ApiError {
        match e {
            fpc::scene::SceneReadError::Syntax(s) => ApiError::bad("toml", s.to_string()),
            fpc::scene::SceneReadError::Input(i) => i.into(),
        }
    }
}

/// The answer to a panic in a handler (tower-http's `CatchPanicLayer`):
/// 500 with the panic's message; the server goes on.
pub fn panic_response(payload: Box<dyn Any + Send + 'static>) -> Response {
    ApiError::internal(format!(
        "internal error (a bug, please report it): {}",
        fpc::cancel::panic_text(payload.as_ref())
    ))
    .into_response()
}
