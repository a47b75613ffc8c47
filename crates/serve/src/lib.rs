//! `fpc serve`: a local web server with one live page for designing a
//! gripper, and the JSON API the page calls (docs/serve.md).
//!
//! The API answers with the library's own records (the keys of `fpc
//! solve`'s solution.json and of `fpc design`'s design.json); bad input is
//! a 400 naming the field, a failed solve a 422, and a panic a 500 after
//! which the server goes on. Computations run on the blocking pool, a
//! bounded number at once, each stopped when its client goes away or its
//! time runs out; a client gets a bounded time to send its request.
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
use std::time::Duration;

use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use tokio::sync::watch;

pub use api::{app, AppState};
pub use errors::ApiError;

use limits::{HEADER_SECONDS, SHUTDOWN_SECONDS, STOP_SECONDS};

/// Serves `app` on `listener` until `shutdown` completes: HTTP/1.1, a
/// connection closed when its client takes longer than `header_time` to
/// send a request's headers (counted from the connection's start or the
/// end of its last answer, so an idle connection is closed too). Once
/// `shutdown` completes, no connection is accepted and the open ones end
/// after their current answer; the function returns when they have.
pub async fn serve_on(
    listener: tokio::net::TcpListener,
    app: axum::Router,
    header_time: Duration,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    // dropped when shutdown starts; every connection watches for that
    let (stop_tx, stop_rx) = watch::channel(());
    tokio::spawn(async move {
        shutdown.await;
        drop(stop_rx);
    });
    // each connection holds a receiver; all dropped: all connections ended
    let (done_tx, done_rx) = watch::channel(());
    loop {
        let stream = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok((stream, _)) => stream,
                // out of file handles, a reset before accept, ...: the
                // listener itself is fine
                Err(_) => {
                    tokio::time::sleep(Duration::from_millis(10)).await;
                    continue;
                }
            },
            () = stop_tx.closed() => break,
        };
        let service = TowerToHyperService::new(app.clone());
        let stop = stop_tx.clone();
        let done = done_rx.clone();
        tokio::spawn(async move {
            let mut builder = hyper::server::conn::http1::Builder::new();
            builder
                .timer(TokioTimer::new())
                .header_read_timeout(header_time);
            let conn = builder.serve_connection(TokioIo::new(stream), service);
            let mut conn = std::pin::pin!(conn);
            tokio::select! {
                _ = conn.as_mut() => {}
                () = stop.closed() => {
                    conn.as_mut().graceful_shutdown();
                    let _ = conn.await;
                }
            }
            drop(done);
        });
    }
    drop(done_rx);
    drop(listener);
    done_tx.closed().await;
    Ok(())
}

/// Binds `addr`, calls `ready` with the address bound (the port chosen
/// when `addr`'s is 0), and serves [`api::app_on`] until Ctrl-C, with
/// [`HEADER_SECONDS`] for a request's headers. After Ctrl-C the open
/// connections get [`SHUTDOWN_SECONDS`] to end; then the computations
/// still running (or waiting for their turn) are stopped, their requests
/// answered 503 ([`AppState::stop`]), and the function returns once those
/// answers are written, at most [`STOP_SECONDS`] later. Builds its own
/// runtime.
pub fn run(addr: SocketAddr, ready: impl FnOnce(SocketAddr)) -> std::io::Result<()> {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()?;
    let served = rt.block_on(async move {
        let listener = tokio::net::TcpListener::bind(addr).await?;
        ready(listener.local_addr()?);
        let state = AppState::default();
        let (signal_tx, signal_rx) = tokio::sync::oneshot::channel::<()>();
        let server = serve_on(
            listener,
            api::app_on_with(addr, state.clone()),
            Duration::from_secs(HEADER_SECONDS),
            async move {
                let _ = tokio::signal::ctrl_c().await;
                let _ = signal_tx.send(());
            },
        );
        let mut server = std::pin::pin!(server);
        let grace = async move {
            let _ = signal_rx.await;
            tokio::time::sleep(Duration::from_secs(SHUTDOWN_SECONDS)).await;
        };
        tokio::select! {
            served = server.as_mut() => return served,
            () = grace => {}
        }
        state.stop();
        let answered = tokio::time::timeout(Duration::from_secs(STOP_SECONDS), server).await;
        answered.unwrap_or(Ok(()))
    });
    // a stopped computation's thread ends at its next check (its flag is
    // set): not waited for
    rt.shutdown_background();
    served
}
