//! The store's schema, as an ordered list of steps: each engine applies,
//! in one transaction per step, the steps past the version its
//! `schema_version` table records (under a lock, so that processes
//! starting together apply each step once). A step is never edited once
//! released; a change to the schema is a new step.
//!
//! Version 1 is the schema of the first service (jobs and their events);
//! a SQLite store made before versions were recorded has its tables and no
//! `schema_version`, and counts as version 1. Version 2 adds users and
//! their tokens, each job's owner, what a job was submitted with
//! (`force_limits`, `checkpoint_every`), leases, a per-job event counter
//! and the workers' counters.

/// One step of the schema.
pub struct Migration {
    /// The version it brings the store to.
    pub version: i64,
    /// What it says to SQLite.
    pub sqlite: &'static str,
    /// What it says to PostgreSQL.
    pub postgres: &'static str,
}

/// The newest version this build knows.
pub const LATEST: i64 = 2;

/// Every step, in order.
pub const MIGRATIONS: [Migration; 2] = [
    Migration {
        version: 1,
        sqlite: "CREATE TABLE IF NOT EXISTS jobs (
                seq INTEGER PRIMARY KEY AUTOINCREMENT,
                id TEXT NOT NULL UNIQUE,
                kind TEXT NOT NULL,
                config TEXT NOT NULL,
                seed INTEGER,
                state TEXT NOT NULL,
                created_ms INTEGER NOT NULL,
                started_ms INTEGER,
                finished_ms INTEGER,
                attempts INTEGER NOT NULL DEFAULT 0,
                resume INTEGER NOT NULL DEFAULT 0,
                cancel_requested INTEGER NOT NULL DEFAULT 0,
                progress TEXT,
                summary TEXT,
                error TEXT
            );
            CREATE INDEX IF NOT EXISTS jobs_by_state ON jobs (state, seq);
            CREATE TABLE IF NOT EXISTS events (
                job TEXT NOT NULL,
                seq INTEGER NOT NULL,
                data TEXT NOT NULL,
                PRIMARY KEY (job, seq)
            ) WITHOUT ROWID;",
        postgres: "CREATE TABLE jobs (
                seq BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
                id TEXT NOT NULL UNIQUE,
                kind TEXT NOT NULL,
                config TEXT NOT NULL,
                seed BIGINT,
                state TEXT NOT NULL,
                created_ms BIGINT NOT NULL,
                started_ms BIGINT,
                finished_ms BIGINT,
                attempts BIGINT NOT NULL DEFAULT 0,
                resume BOOLEAN NOT NULL DEFAULT FALSE,
                cancel_requested BOOLEAN NOT NULL DEFAULT FALSE,
                progress TEXT,
                summary TEXT,
                error TEXT
            );
            CREATE INDEX jobs_by_state ON jobs (state, seq);
            CREATE TABLE events (
                job TEXT NOT NULL,
                seq BIGINT NOT NULL,
                data TEXT NOT NULL,
                PRIMARY KEY (job, seq)
            );",
    },
    Migration {
        version: 2,
        sqlite: "CREATE TABLE users (
                id INTEGER PRIMARY KEY AUTOINCREMENT,
                name TEXT NOT NULL UNIQUE,
                role TEXT NOT NULL CHECK (role IN ('user', 'admin')),
                created_ms INTEGER NOT NULL,
                max_queued INTEGER,
                max_particles INTEGER
            );
            INSERT INTO users (id, name, role, created_ms)
                VALUES (1, 'admin', 'admin', CAST(unixepoch('subsec') * 1000 AS INTEGER));
            CREATE TABLE tokens (
                hash BLOB PRIMARY KEY,
                user_id INTEGER NOT NULL REFERENCES users (id),
                created_ms INTEGER NOT NULL,
                revoked_ms INTEGER
            );
            CREATE INDEX tokens_by_user ON tokens (user_id);
            ALTER TABLE jobs ADD COLUMN owner INTEGER NOT NULL DEFAULT 1;
            ALTER TABLE jobs ADD COLUMN force_limits INTEGER NOT NULL DEFAULT 0;
            ALTER TABLE jobs ADD COLUMN checkpoint_every INTEGER NOT NULL DEFAULT 10;
            ALTER TABLE jobs ADD COLUMN worker TEXT;
            ALTER TABLE jobs ADD COLUMN lease INTEGER;
            ALTER TABLE jobs ADD COLUMN lease_until_ms INTEGER;
            ALTER TABLE jobs ADD COLUMN last_event INTEGER NOT NULL DEFAULT 0;
            UPDATE jobs SET last_event =
                (SELECT COALESCE(MAX(seq), 0) FROM events WHERE events.job = jobs.id);
            CREATE INDEX jobs_by_owner ON jobs (owner, state, seq);
            CREATE TABLE workers (
                name TEXT PRIMARY KEY,
                seen_ms INTEGER NOT NULL,
                claimed INTEGER NOT NULL DEFAULT 0,
                finished INTEGER NOT NULL DEFAULT 0,
                leases_lost INTEGER NOT NULL DEFAULT 0
            );
            CREATE TABLE lease_numbers (last INTEGER NOT NULL);
            INSERT INTO lease_numbers (last) VALUES (0);",
        postgres: "CREATE TABLE users (
                id BIGINT GENERATED BY DEFAULT AS IDENTITY PRIMARY KEY,
                name TEXT NOT NULL UNIQUE,
                role TEXT NOT NULL CHECK (role IN ('user', 'admin')),
                created_ms BIGINT NOT NULL,
                max_queued BIGINT,
                max_particles BIGINT
            );
            INSERT INTO users (id, name, role, created_ms)
                VALUES (1, 'admin', 'admin', (extract(epoch from clock_timestamp()) * 1000)::BIGINT);
            SELECT setval(pg_get_serial_sequence('users', 'id'), 1);
            CREATE TABLE tokens (
                hash BYTEA PRIMARY KEY,
                user_id BIGINT NOT NULL REFERENCES users (id),
                created_ms BIGINT NOT NULL,
                revoked_ms BIGINT
            );
            CREATE INDEX tokens_by_user ON tokens (user_id);
            ALTER TABLE jobs ADD COLUMN owner BIGINT NOT NULL DEFAULT 1 REFERENCES users (id);
            ALTER TABLE jobs ADD COLUMN force_limits BOOLEAN NOT NULL DEFAULT FALSE;
            ALTER TABLE jobs ADD COLUMN checkpoint_every BIGINT NOT NULL DEFAULT 10;
            ALTER TABLE jobs ADD COLUMN worker TEXT;
            ALTER TABLE jobs ADD COLUMN lease BIGINT;
            ALTER TABLE jobs ADD COLUMN lease_until_ms BIGINT;
            ALTER TABLE jobs ADD COLUMN last_event BIGINT NOT NULL DEFAULT 0;
            CREATE INDEX jobs_by_owner ON jobs (owner, state, seq);
            CREATE INDEX jobs_by_lease ON jobs (lease_until_ms) WHERE state = 'running';
            CREATE TABLE workers (
                name TEXT PRIMARY KEY,
                seen_ms BIGINT NOT NULL,
                claimed BIGINT NOT NULL DEFAULT 0,
                finished BIGINT NOT NULL DEFAULT 0,
                leases_lost BIGINT NOT NULL DEFAULT 0
            );
            CREATE SEQUENCE lease_numbers;
            CREATE FUNCTION gapack_now_ms() RETURNS BIGINT LANGUAGE SQL VOLATILE
                AS $$ SELECT (extract(epoch from clock_timestamp()) * 1000)::BIGINT $$;",
    },
];
