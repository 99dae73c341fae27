//! The service's users (`gapack user`): adding one makes a token, shown
//! once, of which the store keeps only the SHA-256; revoking one refuses
//! their tokens from the next request on, on every front.
//!
//! A token is `gpk_` and 64 hex digits (256 random bits): too many to
//! guess, so a plain SHA-256 (no slow hash) keeps it safe in the store,
//! and a lookup by hash shows nothing of the token by its timing.

use sha2::{Digest, Sha256};

use super::store::{self, Role, StoreError, StoreUrl, User};

/// The SHA-256 of `token`, as the store keeps it.
pub fn token_hash(token: &str) -> [u8; 32] {
    Sha256::digest(token.as_bytes()).into()
}

/// A new token: `gpk_` and 64 hex digits from the system's random source.
fn new_token() -> String {
    let bytes: [u8; 32] = rand::random();
    let mut token = String::with_capacity(4 + 64);
    token.push_str("gpk_");
    for b in bytes {
        token.push_str(&format!("{b:02x}"));
    }
    token
}

/// What a new user may do.
#[derive(Debug, Clone, Copy)]
pub struct NewUser<'a> {
    /// Their name: 1 to 64 letters, digits, `.`, `_`, `-` or `@`.
    pub name: &'a str,
    /// Their role.
    pub role: Role,
    /// Most jobs they may have waiting (`None`: the server's default).
    pub max_queued: Option<i64>,
    /// Most particles a scene of theirs may hold (`None`: the server's).
    pub max_particles: Option<i64>,
}

/// Why a user command failed.
#[derive(Debug, thiserror::Error)]
pub enum UserError {
    /// A name the service does not take.
    #[error("user name {0:?}: give 1 to 64 letters, digits, '.', '_', '-' or '@'")]
    BadName(String),
    /// No user has that name.
    #[error("no user named {0:?}")]
    NoSuchUser(String),
    /// The store failed.
    #[error(transparent)]
    Store(#[from] StoreError),
}

/// Whether `name` is a user name the service takes.
fn valid_name(name: &str) -> bool {
    (1..=64).contains(&name.len())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-' | '@'))
}

/// Add `user` to the store at `url`: the user and their token (the only
/// time it is seen).
///
/// # Errors
/// [`UserError`]: a bad name, a name taken, a store that failed.
pub fn add(url: &str, user: &NewUser<'_>) -> Result<(User, String), UserError> {
    if !valid_name(user.name) {
        return Err(UserError::BadName(user.name.to_owned()));
    }
    let store = store::open(&StoreUrl::parse(url)?)?;
    let token = new_token();
    let added = store.add_user(
        user.name,
        user.role,
        &token_hash(&token),
        user.max_queued,
        user.max_particles,
    )?;
    Ok((added, token))
}

/// Revoke every token of user `name` in the store at `url`.
///
/// # Errors
/// [`UserError::NoSuchUser`], or a store that failed.
pub fn revoke(url: &str, name: &str) -> Result<(), UserError> {
    let store = store::open(&StoreUrl::parse(url)?)?;
    if store.revoke_user(name)? {
        Ok(())
    } else {
        Err(UserError::NoSuchUser(name.to_owned()))
    }
}

/// Every user of the store at `url`.
///
/// # Errors
/// A store that failed.
pub fn list(url: &str) -> Result<Vec<User>, UserError> {
    let store = store::open(&StoreUrl::parse(url)?)?;
    Ok(store.users()?)
}

#[cfg(test)]
mod tests {
    use super::{new_token, token_hash, valid_name};

    #[test]
    fn tokens_are_long_random_and_hashed_whole() {
        let a = new_token();
        let b = new_token();
        assert_ne!(a, b);
        assert_eq!(a.len(), 68);
        assert!(a.starts_with("gpk_") && a[4..].chars().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(token_hash(&a), token_hash(&b));
        // SHA-256 of "abc" (FIPS 180-2's first example).
        assert_eq!(token_hash("abc")[..4], [0xba, 0x78, 0x16, 0xbf]);
    }

    #[test]
    fn names_are_plain() {
        for good in ["ana", "b.silva", "lab-2", "x@y.org", "A_1"] {
            assert!(valid_name(good), "{good}");
        }
        for bad in ["", "a b", "ação", "a/b", &"x".repeat(65)] {
            assert!(!valid_name(bad), "{bad}");
        }
    }
}
