//! Tenants and the `--auth-tokens` file (docs/design.md §6.6): who a caller is, and the
//! [`TokenTable`] that maps bearer tokens to [`Tenant`]s. A leaf module: everything that
//! keeps per-tenant state (registries, limits, metrics, the dashboard) names tenants from
//! here, and the interceptor that finds a request's tenant is `auth.rs`.

use std::collections::HashMap;
use std::fmt;
use std::path::Path;
use std::sync::Arc;

/// Most characters of a tenant name.
const MAX_TENANT_NAME: usize = 64;
/// Fewest characters of a token: shorter ones are guessable.
pub const MIN_TOKEN_CHARS: usize = 16;
/// Most tokens one file may hold (a file of millions is a mistake, not a configuration).
const MAX_TOKENS: usize = 100_000;

/// Who is calling: a tenant from the token file, or the anonymous tenant when auth is off.
#[derive(Clone, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Tenant(Arc<str>);

impl Tenant {
    /// The tenant of every caller when auth is off (its name is empty).
    pub fn anonymous() -> Self {
        Tenant::default()
    }

    /// A tenant by name (names are checked where they are read, in [`TokenTable::parse`]).
    pub(crate) fn named(name: &str) -> Self {
        Tenant(Arc::from(name))
    }

    /// The tenant's name; empty for the anonymous tenant.
    pub fn name(&self) -> &str {
        &self.0
    }
}

impl fmt::Debug for Tenant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Tenant({:?})", self.name())
    }
}

impl fmt::Display for Tenant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            f.write_str("(anonymous)")
        } else {
            f.write_str(&self.0)
        }
    }
}

/// The tokens of an `--auth-tokens` file, each mapped to its tenant.
#[derive(Clone, PartialEq, Eq)]
pub struct TokenTable {
    tokens: HashMap<String, Tenant>,
}

impl fmt::Debug for TokenTable {
    // Never print the tokens themselves.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TokenTable")
            .field("tenants", &self.tenants())
            .field("tokens", &self.tokens.len())
            .finish()
    }
}

impl TokenTable {
    /// Parses the file format: one `TENANT TOKEN` pair per line, `#` starts a comment,
    /// blank lines are skipped; a tenant may have several tokens. Errors name the line.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut tokens = HashMap::new();
        for (i, line) in text.lines().enumerate() {
            let line_no = i + 1;
            let line = line.split('#').next().unwrap_or_default().trim();
            if line.is_empty() {
                continue;
            }
            let mut fields = line.split_whitespace();
            let (Some(tenant), Some(token), None) = (fields.next(), fields.next(), fields.next())
            else {
                return Err(format!(
                    "line {line_no}: expected `TENANT TOKEN` (two fields separated by spaces)"
                ));
            };
            check_tenant_name(tenant).map_err(|e| format!("line {line_no}: {e}"))?;
            if token.chars().count() < MIN_TOKEN_CHARS {
                return Err(format!(
                    "line {line_no}: the token of tenant {tenant:?} has fewer than \
                     {MIN_TOKEN_CHARS} characters"
                ));
            }
            if tokens.len() >= MAX_TOKENS {
                return Err(format!("more than {MAX_TOKENS} tokens"));
            }
            let tenant = Tenant::named(tenant);
            if let Some(other) = tokens.insert(token.to_string(), tenant.clone()) {
                if other != tenant {
                    return Err(format!(
                        "line {line_no}: this token is already the token of tenant {other}; \
                         a token names exactly one tenant"
                    ));
                }
            }
        }
        if tokens.is_empty() {
            return Err("no tokens: the file has no `TENANT TOKEN` line".to_string());
        }
        Ok(TokenTable { tokens })
    }

    /// Reads and parses a token file; errors name the file.
    pub fn load(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("--auth-tokens {}: {e}", path.display()))?;
        Self::parse(&text).map_err(|e| format!("--auth-tokens {}: {e}", path.display()))
    }

    /// The tenant a token belongs to.
    pub fn tenant(&self, token: &str) -> Option<&Tenant> {
        self.tokens.get(token)
    }

    /// The tenants' names, sorted, each once.
    pub fn tenants(&self) -> Vec<&str> {
        let mut names: Vec<&str> = self.tokens.values().map(Tenant::name).collect();
        names.sort_unstable();
        names.dedup();
        names
    }
}

fn check_tenant_name(name: &str) -> Result<(), String> {
    let valid = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.');
    if name.len() > MAX_TENANT_NAME || !name.chars().all(valid) {
        return Err(format!(
            "tenant names are 1 to {MAX_TENANT_NAME} characters of A-Z a-z 0-9 _ - ."
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOKEN_A: &str = "alpha-0123456789abcdef";
    const TOKEN_B: &str = "beta-0123456789abcdef";

    fn table() -> TokenTable {
        TokenTable::parse(&format!(
            "# tenants\n\nteam-a {TOKEN_A}  # first\nteam-a {TOKEN_A}x\n  team_b\t{TOKEN_B}\n"
        ))
        .unwrap()
    }

    #[test]
    fn the_file_maps_tokens_to_tenants() {
        let t = table();
        assert_eq!(t.tenant(TOKEN_A).unwrap().name(), "team-a");
        assert_eq!(t.tenant(&format!("{TOKEN_A}x")).unwrap().name(), "team-a");
        assert_eq!(t.tenant(TOKEN_B).unwrap().name(), "team_b");
        assert_eq!(t.tenant("nope"), None);
        assert_eq!(t.tenants(), ["team-a", "team_b"]);
        assert!(!format!("{t:?}").contains(TOKEN_A), "Debug hides tokens");
    }

    #[test]
    fn bad_files_name_the_line() {
        let cases = [
            ("", "no tokens: the file has no `TENANT TOKEN` line"),
            (
                "a",
                "line 1: expected `TENANT TOKEN` (two fields separated by spaces)",
            ),
            (
                "# c\na b c",
                "line 2: expected `TENANT TOKEN` (two fields separated by spaces)",
            ),
            (
                "a short",
                "line 1: the token of tenant \"a\" has fewer than 16 characters",
            ),
            (
                "a/b 0123456789abcdef",
                "line 1: tenant names are 1 to 64 characters of A-Z a-z 0-9 _ - .",
            ),
            (
                "a 0123456789abcdef\nb 0123456789abcdef",
                "line 2: this token is already the token of tenant a; a token names \
                 exactly one tenant",
            ),
        ];
        for (text, message) in cases {
            assert_eq!(TokenTable::parse(text).unwrap_err(), message, "{text:?}");
        }
    }
}
