//! `fpc serve`: a local web server with one live page for designing a
//! gripper, and the JSON API the page calls (docs/serve.md).
//!
//! The API answers with the library's own records (the keys of `fpc
//! solve`'s solution.json and of `fpc design`'s design.json); bad input is
//! a 400 naming the field, a failed solve a 422, and a panic a 500 after
//! which the server goes on. Computations run on the blocking pool, a
//! bounded number at once, each stopped when its client goes away or its
//! time runs out.
//!
//! The modules: [`api`] (the router, its layers and the blocking runner),
//! [`handlers`] (the computations, one per endpoint), [`assets`] (the
//! page), [`limits`] (what a request may ask for), [`errors`] (the error
//! answers).

pub mod api;
pub mod assets;
pub mod errors;
pub mod handlers;
pub mod limits;

use std::future::Future;
use std::net::SocketAddr;

pub use api::{app, AppState};
pub use errors::ApiError;

/// Serves [`app`] on `listener` until `shutdown` completes.
pub async fn serve_on(
    listener: tokio::net::TcpListener,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    axum::serve(listener, app())
        .with_graceful_shutdown(shutdown)
        .await
}

/// Binds `addr`, calls `ready` with the address bound (the port chosen
/// when `addr`'s is 0), and serves until Ctrl-C. Builds its own runtime.
pub fn run(addr: SocketAddr, ready: impl FnOnce(SocketAddr)) -> std::io::Result<()> {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()?;
    rt.block_on(async move {
        let listener = tokio::net::TcpListener::bind(addr).await?;
        ready(listener.local_addr()?);
        serve_on(listener, async {
            let _ = tokio::signal::ctrl_c().await;
        })
        .await
    })
}
