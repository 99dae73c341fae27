//! The store's queries: the queue and its leases, jobs as each caller
//! sees them, their events, users and tokens, workers.

use std::sync::mpsc;
use std::time::Duration;

use serde_json::json;

// The connection, the query helpers and the SQL pieces of the parent.
use super::listen::listen;
use super::*;

impl JobStore for PgStore {
    fn engine(&self) -> &'static str {
        "postgres"
    }

    /// Nothing: jobs whose worker died come back through their leases
    /// ([`JobStore::reap`]), while the other processes' jobs run on.
    fn recover(&self) -> Result<usize, StoreError> {
        Ok(0)
    }

    fn insert(&self, job: &NewJob<'_>, limits: QueueLimits) -> Result<(), StoreError> {
        self.write(async |tx| {
            tx.execute("SELECT pg_advisory_xact_lock($1)", &[&QUEUE_LOCK])
                .await?;
            let counted = one(
                tx,
                "SELECT count(*), count(*) FILTER (WHERE owner = $1) FROM jobs \
                 WHERE state = 'queued'",
                &[&job.owner.id],
            )
            .await?;
            let (queued, mine): (i64, i64) = (counted.try_get(0)?, counted.try_get(1)?);
            if usize::try_from(queued).unwrap_or(usize::MAX) >= limits.total {
                return Err(StoreError::QueueFull(limits.total));
            }
            let share = job
                .owner
                .max_queued
                .map_or(limits.per_user, |n| usize::try_from(n).unwrap_or(0));
            if usize::try_from(mine).unwrap_or(usize::MAX) >= share {
                return Err(StoreError::UserQueueFull(share));
            }
            exec(
                tx,
                "INSERT INTO jobs (id, owner, kind, config, seed, force_limits, checkpoint_every, \
                 state, created_ms) VALUES ($1, $2, $3, $4, $5, $6, $7, 'queued', gapack_now_ms())",
                &[
                    &job.id,
                    &job.owner.id,
                    &job.kind,
                    &job.config,
                    &job.seed.map(|s| s as i64),
                    &job.force,
                    &job.checkpoint_every,
                ],
            )
            .await?;
            append(tx, job.id, &state_event(State::Queued)).await?;
            notify(tx, "gapack_queue", "").await?;
            Ok(())
        })
    }

    fn claim(&self, worker: &str, ttl: Duration) -> Result<Option<Claimed>, StoreError> {
        let ttl = millis(ttl);
        self.write(async |tx| {
            let Some(found) = opt(
                tx,
                "SELECT j.seq FROM jobs j WHERE j.state = 'queued' ORDER BY \
                 (SELECT count(*) FROM jobs r WHERE r.owner = j.owner AND r.state = 'running'), \
                 j.seq LIMIT 1 FOR UPDATE SKIP LOCKED",
                &[],
            )
            .await?
            else {
                return Ok(None);
            };
            let seq: i64 = found.try_get(0)?;
            let claimed = one(
                tx,
                "UPDATE jobs SET state = 'running', started_ms = gapack_now_ms(), \
                 attempts = attempts + 1, worker = $2, lease = nextval('lease_numbers'), \
                 lease_until_ms = gapack_now_ms() + $3 WHERE seq = $1 RETURNING id, lease",
                &[&seq, &worker, &ttl],
            )
            .await?;
            let (id, lease): (String, i64) = (claimed.try_get(0)?, claimed.try_get(1)?);
            exec(
                tx,
                "INSERT INTO workers (name, seen_ms, claimed) VALUES ($1, gapack_now_ms(), 1) \
                 ON CONFLICT (name) DO UPDATE SET seen_ms = EXCLUDED.seen_ms, \
                 claimed = workers.claimed + 1",
                &[&worker],
            )
            .await?;
            let job = job_row(
                &one(
                    tx,
                    &format!("SELECT {COLUMNS} FROM {FROM} WHERE j.seq = $1"),
                    &[&seq],
                )
                .await?,
            )?;
            append(
                tx,
                &id,
                &json!({"event": "state", "state": "running", "attempt": job.attempts, "resume": job.resume}),
            )
            .await?;
            Ok(Some(Claimed { job, lease }))
        })
    }

    fn heartbeat(
        &self,
        worker: &str,
        id: &str,
        lease: i64,
        ttl: Duration,
    ) -> Result<Beat, StoreError> {
        let ttl = millis(ttl);
        self.write(async |tx| {
            let asked = opt(
                tx,
                "UPDATE jobs SET lease_until_ms = gapack_now_ms() + $3 WHERE id = $1 \
                 AND state = 'running' AND lease = $2 RETURNING cancel_requested",
                &[&id, &lease, &ttl],
            )
            .await?;
            match asked {
                Some(r) => {
                    let cancel_requested: bool = r.try_get(0)?;
                    exec(
                        tx,
                        "UPDATE workers SET seen_ms = gapack_now_ms() WHERE name = $1",
                        &[&worker],
                    )
                    .await?;
                    Ok(Beat::Held { cancel_requested })
                }
                // Counted once, by the reaper that took the lease.
                None => Ok(Beat::Lost),
            }
        })
    }

    fn event(
        &self,
        id: &str,
        lease: i64,
        data: &serde_json::Value,
        progress: bool,
    ) -> Result<Option<i64>, StoreError> {
        // One statement, one round trip (a job sends an event per
        // generation): the lease checked, the counter bumped and the
        // progress kept under the row's lock, the event inserted, the
        // listeners told at commit; no row when the lease is gone.
        let data = data.to_string();
        self.read(async |c| {
            let row = opt(
                c,
                "WITH j AS (UPDATE jobs SET last_event = last_event + 1, \
                   progress = CASE WHEN $4 THEN $3 ELSE progress END \
                   WHERE id = $1 AND state = 'running' AND lease = $2 RETURNING last_event), \
                 e AS (INSERT INTO events (job, seq, data) SELECT $1, last_event, $3 FROM j \
                   RETURNING seq) \
                 SELECT seq, pg_notify('gapack_events', $1) FROM e",
                &[&id, &lease, &data, &progress],
            )
            .await?;
            Ok(row.map(|r| r.try_get(0)).transpose()?)
        })
    }

    fn finish(
        &self,
        worker: &str,
        id: &str,
        lease: i64,
        ending: &Ending,
    ) -> Result<bool, StoreError> {
        self.write(async |tx| {
            if !holds(tx, id, lease).await? {
                return Ok(false);
            }
            match ending {
                Ending::Final {
                    state,
                    summary,
                    error,
                } => {
                    exec(
                        tx,
                        "UPDATE jobs SET state = $2, finished_ms = gapack_now_ms(), summary = $3, \
                         error = $4, worker = NULL, lease = NULL, lease_until_ms = NULL \
                         WHERE id = $1",
                        &[&id, &state.name(), summary, error],
                    )
                    .await?;
                    let mut event = state_event(*state);
                    if let Some(error) = error {
                        event["error"] = json!(error);
                    }
                    append(tx, id, &event).await?;
                }
                Ending::Requeue => {
                    exec(
                        tx,
                        "UPDATE jobs SET state = 'queued', resume = TRUE, worker = NULL, \
                         lease = NULL, lease_until_ms = NULL WHERE id = $1",
                        &[&id],
                    )
                    .await?;
                    append(
                        tx,
                        id,
                        &json!({"event": "state", "state": "queued", "reason": "its worker stopped"}),
                    )
                    .await?;
                    notify(tx, "gapack_queue", "").await?;
                }
            }
            exec(
                tx,
                "UPDATE workers SET finished = finished + 1, seen_ms = gapack_now_ms() \
                 WHERE name = $1",
                &[&worker],
            )
            .await?;
            Ok(true)
        })
    }

    fn reap(&self) -> Result<Vec<Reaped>, StoreError> {
        self.write(async |tx| {
            let expired = rows(
                tx,
                "SELECT id, worker, attempts, cancel_requested FROM jobs \
                 WHERE state = 'running' AND lease_until_ms < gapack_now_ms() \
                 ORDER BY seq FOR UPDATE SKIP LOCKED",
                &[],
            )
            .await?;
            let mut reaped = Vec::with_capacity(expired.len());
            for r in &expired {
                let id: String = r.try_get(0)?;
                let worker: Option<String> = r.try_get(1)?;
                let state = requeue(tx, &id, r.try_get(2)?, r.try_get(3)?).await?;
                reaped.push(Reaped { id, state, worker });
            }
            if reaped.iter().any(|r| r.state == State::Queued) {
                notify(tx, "gapack_queue", "").await?;
            }
            // The workers' counters, in the order of their names (two
            // reapers lock them in one order: no deadlock).
            let mut lost: Vec<&str> = reaped.iter().filter_map(|r| r.worker.as_deref()).collect();
            lost.sort_unstable();
            for worker in lost {
                exec(
                    tx,
                    "UPDATE workers SET leases_lost = leases_lost + 1 WHERE name = $1",
                    &[&worker],
                )
                .await?;
            }
            Ok(reaped)
        })
    }

    fn cancel(&self, who: &Caller, id: &str) -> Result<Option<CancelOutcome>, StoreError> {
        self.write(async |tx| {
            let Some(state) = visible_state(tx, who, id).await? else {
                return Ok(None);
            };
            Ok(Some(match state {
                State::Queued => {
                    exec(
                        tx,
                        "UPDATE jobs SET state = 'cancelled', finished_ms = gapack_now_ms() \
                         WHERE id = $1",
                        &[&id],
                    )
                    .await?;
                    append(tx, id, &state_event(State::Cancelled)).await?;
                    CancelOutcome::Dequeued
                }
                State::Running => {
                    exec(
                        tx,
                        "UPDATE jobs SET cancel_requested = TRUE WHERE id = $1",
                        &[&id],
                    )
                    .await?;
                    notify(tx, "gapack_cancel", id).await?;
                    CancelOutcome::Stopping
                }
                done => CancelOutcome::Finished(done),
            }))
        })
    }

    fn cancel_requested(&self, id: &str) -> Result<bool, StoreError> {
        self.read(async |c| {
            let found = opt(c, "SELECT cancel_requested FROM jobs WHERE id = $1", &[&id]).await?;
            Ok(match found {
                Some(r) => r.try_get(0)?,
                None => false,
            })
        })
    }

    fn get(&self, who: &Caller, id: &str) -> Result<Option<JobRow>, StoreError> {
        self.read(async |c| {
            let found = opt(
                c,
                &format!("SELECT {COLUMNS} FROM {FROM} WHERE {VISIBLE}"),
                &[&id, &who.id, &who.admin],
            )
            .await?;
            Ok(found.as_ref().map(job_row).transpose()?)
        })
    }

    fn list(
        &self,
        who: &Caller,
        state: Option<State>,
        before: Option<i64>,
        limit: usize,
    ) -> Result<Vec<JobRow>, StoreError> {
        self.read(async |c| {
            let found = rows(
                c,
                &format!(
                    "SELECT {COLUMNS} FROM {FROM} WHERE ($1::TEXT IS NULL OR j.state = $1::TEXT) \
                     AND j.seq < $2 AND ($5 OR j.owner = $4) ORDER BY j.seq DESC LIMIT $3"
                ),
                &[
                    &state.map(State::name),
                    &before.unwrap_or(i64::MAX),
                    &limit_i64(limit),
                    &who.id,
                    &who.admin,
                ],
            )
            .await?;
            Ok(found.iter().map(job_row).collect::<PgResult<_>>()?)
        })
    }

    fn delete(&self, who: &Caller, id: &str) -> Result<Option<Result<(), State>>, StoreError> {
        self.write(async |tx| {
            let Some(state) = visible_state(tx, who, id).await? else {
                return Ok(None);
            };
            if !state.is_final() {
                return Ok(Some(Err(state)));
            }
            exec(tx, "DELETE FROM events WHERE job = $1", &[&id]).await?;
            exec(tx, "DELETE FROM jobs WHERE id = $1", &[&id]).await?;
            // Streams following it elsewhere look again, and end.
            notify(tx, "gapack_events", id).await?;
            Ok(Some(Ok(())))
        })
    }

    fn events_after(
        &self,
        id: &str,
        after: i64,
        limit: usize,
    ) -> Result<Vec<(i64, String)>, StoreError> {
        self.read(async |c| {
            let found = rows(
                c,
                "SELECT seq, data FROM events WHERE job = $1 AND seq > $2 ORDER BY seq LIMIT $3",
                &[&id, &after, &limit_i64(limit)],
            )
            .await?;
            Ok(found
                .iter()
                .map(|r| Ok((r.try_get(0)?, r.try_get(1)?)))
                .collect::<PgResult<_>>()?)
        })
    }

    fn counts(&self) -> Result<Vec<(State, i64)>, StoreError> {
        self.read(async |c| {
            let found: Vec<(String, i64)> =
                rows(c, "SELECT state, count(*) FROM jobs GROUP BY state", &[])
                    .await?
                    .iter()
                    .map(|r| Ok((r.try_get(0)?, r.try_get(1)?)))
                    .collect::<PgResult<_>>()?;
            Ok(State::ALL
                .into_iter()
                .map(|s| {
                    let n = found
                        .iter()
                        .find(|(name, _)| name == s.name())
                        .map_or(0, |(_, n)| *n);
                    (s, n)
                })
                .collect())
        })
    }

    fn counts_by_user(&self) -> Result<Vec<UserCount>, StoreError> {
        self.read(async |c| {
            // Ordered by bytes, as SQLite orders them, whatever the
            // database's collation.
            let found: Vec<(String, String, i64)> = rows(
                c,
                "SELECT u.name, j.state, count(*) FROM jobs j JOIN users u ON u.id = j.owner \
                 GROUP BY u.name, j.state ORDER BY u.name COLLATE \"C\", j.state COLLATE \"C\"",
                &[],
            )
            .await?
            .iter()
            .map(|r| Ok((r.try_get(0)?, r.try_get(1)?, r.try_get(2)?)))
            .collect::<PgResult<_>>()?;
            Ok(found
                .into_iter()
                .filter_map(|(user, state, jobs)| {
                    State::parse(&state).map(|state| UserCount { user, state, jobs })
                })
                .collect())
        })
    }

    fn workers(&self) -> Result<Vec<WorkerRow>, StoreError> {
        self.read(async |c| {
            Ok(rows(
                c,
                "SELECT name, seen_ms, claimed, finished, leases_lost FROM workers \
                 ORDER BY name COLLATE \"C\"",
                &[],
            )
            .await?
            .iter()
            .map(|r| {
                Ok(WorkerRow {
                    name: r.try_get(0)?,
                    seen_ms: r.try_get(1)?,
                    claimed: r.try_get(2)?,
                    finished: r.try_get(3)?,
                    leases_lost: r.try_get(4)?,
                })
            })
            .collect::<PgResult<_>>()?)
        })
    }

    fn alive(&self, names: &[String]) -> Result<(), StoreError> {
        self.read(async |c| {
            exec(
                c,
                "INSERT INTO workers (name, seen_ms) SELECT unnest($1::TEXT[]), gapack_now_ms() \
                 ON CONFLICT (name) DO UPDATE SET seen_ms = EXCLUDED.seen_ms",
                &[&names],
            )
            .await?;
            Ok(())
        })
    }

    fn add_user(
        &self,
        name: &str,
        role: Role,
        token_hash: &[u8; 32],
        max_queued: Option<i64>,
        max_particles: Option<i64>,
    ) -> Result<User, StoreError> {
        self.write(async |tx| {
            // A name taken, even by a user added at the same moment,
            // inserts nothing.
            let Some(added) = opt(
                tx,
                "INSERT INTO users (name, role, created_ms, max_queued, max_particles) \
                 VALUES ($1, $2, gapack_now_ms(), $3, $4) ON CONFLICT (name) DO NOTHING \
                 RETURNING id",
                &[&name, &role.name(), &max_queued, &max_particles],
            )
            .await?
            else {
                return Err(StoreError::UserExists(name.to_owned()));
            };
            let id: i64 = added.try_get(0)?;
            exec(
                tx,
                "INSERT INTO tokens (hash, user_id, created_ms) VALUES ($1, $2, gapack_now_ms())",
                &[&&token_hash[..], &id],
            )
            .await?;
            Ok(User {
                id,
                name: name.to_owned(),
                role,
                max_queued,
                max_particles,
                tokens: 1,
            })
        })
    }

    fn revoke_user(&self, name: &str) -> Result<bool, StoreError> {
        self.write(async |tx| {
            let Some(found) = opt(tx, "SELECT id FROM users WHERE name = $1", &[&name]).await?
            else {
                return Ok(false);
            };
            let id: i64 = found.try_get(0)?;
            exec(
                tx,
                "UPDATE tokens SET revoked_ms = gapack_now_ms() \
                 WHERE user_id = $1 AND revoked_ms IS NULL",
                &[&id],
            )
            .await?;
            Ok(true)
        })
    }

    fn users(&self) -> Result<Vec<User>, StoreError> {
        self.read(async |c| {
            Ok(rows(
                c,
                &format!("SELECT {USER_COLUMNS} FROM users u ORDER BY u.id"),
                &[],
            )
            .await?
            .iter()
            .map(user_row)
            .collect::<PgResult<_>>()?)
        })
    }

    fn user_by_token(&self, token_hash: &[u8; 32]) -> Result<Option<Caller>, StoreError> {
        self.read(async |c| {
            let found = opt(
                c,
                &format!(
                    "SELECT {USER_COLUMNS} FROM tokens t JOIN users u ON u.id = t.user_id \
                     WHERE t.hash = $1 AND t.revoked_ms IS NULL"
                ),
                &[&&token_hash[..]],
            )
            .await?;
            Ok(found.as_ref().map(user_row).transpose()?.map(Caller::from))
        })
    }

    fn user_named(&self, name: &str) -> Result<Option<Caller>, StoreError> {
        self.read(async |c| {
            let found = opt(
                c,
                &format!("SELECT {USER_COLUMNS} FROM users u WHERE u.name = $1"),
                &[&name],
            )
            .await?;
            Ok(found.as_ref().map(user_row).transpose()?.map(Caller::from))
        })
    }

    fn has_tokens(&self) -> Result<bool, StoreError> {
        self.read(async |c| {
            Ok(one(c, "SELECT EXISTS (SELECT 1 FROM tokens)", &[])
                .await?
                .try_get(0)?)
        })
    }

    /// Every call starts a listener of its own (its own connection to the
    /// database, outside the pool) and returns its receiver: the listener
    /// ends at its first notice after the receiver is dropped, or with the
    /// store (then the receiver reports the sender gone).
    fn subscribe(&self) -> Option<mpsc::Receiver<Notice>> {
        let runtime = self.runtime.as_ref()?;
        let (to, from) = mpsc::channel();
        runtime.spawn(listen(self.config.clone(), to));
        Some(from)
    }
}
