//! Notifications from the other processes sharing the store, on a
//! connection of the listener's own (a pooled one would drop its `LISTEN`
//! when handed back).

use std::sync::mpsc;

use futures_util::StreamExt;
use tokio_postgres::{AsyncMessage, NoTls};

use super::{LISTEN, RELISTEN};
use crate::store::Notice;

/// Follow the store's channels on a connection of its own, sending what
/// comes to `to`, until `to`'s receiver is gone. A lost connection is
/// made again every [`RELISTEN`]; then [`Notice::Resync`] says that
/// news may have been missed.
pub(super) async fn listen(config: tokio_postgres::Config, to: mpsc::Sender<Notice>) {
    let mut missed = false;
    // Ends when the receiver is gone (a send fails), or with the store's
    // runtime.
    loop {
        if let Ok((client, mut connection)) = config.connect(NoTls).await {
            let (found, mut news) = tokio::sync::mpsc::unbounded_channel();
            let driver = tokio::spawn(async move {
                let mut messages =
                    futures_util::stream::poll_fn(move |cx| connection.poll_message(cx));
                while let Some(Ok(message)) = messages.next().await {
                    if let AsyncMessage::Notification(n) = message
                        && found
                            .send((n.channel().to_owned(), n.payload().to_owned()))
                            .is_err()
                    {
                        break;
                    }
                }
            });
            if client.batch_execute(LISTEN).await.is_ok() {
                if missed && to.send(Notice::Resync).is_err() {
                    driver.abort();
                    return;
                }
                // Until the connection ends (the driver drops `found`).
                while let Some((channel, payload)) = news.recv().await {
                    let notice = match channel.as_str() {
                        "gapack_events" => Notice::Event(payload),
                        "gapack_queue" => Notice::Queued,
                        "gapack_cancel" => Notice::Cancel(payload),
                        _ => continue,
                    };
                    if to.send(notice).is_err() {
                        driver.abort();
                        return;
                    }
                }
            }
            driver.abort();
        }
        missed = true;
        tokio::time::sleep(RELISTEN).await;
    }
}
