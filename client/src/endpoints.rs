//! [`FleetEndpoints`]: the addresses of a fleet's servers, one per server, from a list,
//! a comma-separated string, or a Kubernetes StatefulSet behind a headless Service.

use std::collections::HashSet;
use std::str::FromStr;

use crate::error::{ClientError, Result};

/// The servers of a fleet, one address (`host:port` or `http://host:port`) each.
///
/// Each address must reach exactly one server process: an env's state lives on one
/// server, so a fleet needs one connection per server, never a load-balanced address.
/// On Kubernetes that is the per-pod DNS name a headless Service gives each pod of a
/// StatefulSet, which [`FleetEndpoints::stateful_set`] spells out.
///
/// ```
/// use gymfleet_client::FleetEndpoints;
///
/// let pods = FleetEndpoints::stateful_set("gymfleet", "gymfleet", "sim", 3, 50051)?;
/// assert_eq!(
///     pods.addrs()[2],
///     "gymfleet-2.gymfleet.sim.svc.cluster.local:50051"
/// );
/// let listed: FleetEndpoints = "10.0.0.5:50051, 10.0.0.6:50051".parse()?;
/// assert_eq!(listed.len(), 2);
/// # Ok::<(), gymfleet_client::ClientError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FleetEndpoints {
    addrs: Vec<String>,
}

fn fleet_error(message: impl Into<String>) -> ClientError {
    ClientError::Fleet {
        message: message.into(),
    }
}

impl FleetEndpoints {
    /// The given addresses, in order. Fails if there are none, if one is empty or holds
    /// whitespace or a comma, or if one is repeated.
    pub fn new<S: Into<String>>(addrs: impl IntoIterator<Item = S>) -> Result<Self> {
        let addrs: Vec<String> = addrs.into_iter().map(Into::into).collect();
        if addrs.is_empty() {
            return Err(fleet_error("no server endpoints given"));
        }
        let mut seen = HashSet::new();
        for addr in &addrs {
            if addr.is_empty() || addr.contains(|c: char| c.is_whitespace() || c == ',') {
                return Err(fleet_error(format!(
                    "endpoint {addr:?}: expected host:port, http://host:port or unix:/path"
                )));
            }
            if !seen.insert(addr.as_str()) {
                return Err(fleet_error(format!(
                    "endpoint {addr} is listed twice; each server must appear once"
                )));
            }
        }
        Ok(FleetEndpoints { addrs })
    }

    /// Parses a comma-separated list, e.g. `"a:50051,b:50051"`; spaces around entries
    /// and empty entries (a trailing comma) are ignored.
    pub fn parse(list: &str) -> Result<Self> {
        Self::new(list.split(',').map(str::trim).filter(|s| !s.is_empty()))
    }

    /// The per-pod addresses of a StatefulSet `name` with `replicas` pods behind the
    /// headless Service `service` in `namespace`:
    /// `<name>-<i>.<service>.<namespace>.svc.cluster.local:<port>` for `i` in
    /// `0..replicas`. The names must be DNS labels (lowercase letters, digits, `-`).
    pub fn stateful_set(
        name: &str,
        service: &str,
        namespace: &str,
        replicas: usize,
        port: u16,
    ) -> Result<Self> {
        for (what, label) in [
            ("statefulset", name),
            ("service", service),
            ("namespace", namespace),
        ] {
            if !is_dns_label(label) {
                return Err(fleet_error(format!(
                    "{what} name {label:?}: expected a DNS label \
                     (1-63 lowercase letters, digits or '-', starting and ending alphanumeric)"
                )));
            }
        }
        if replicas == 0 {
            return Err(fleet_error(
                "a StatefulSet fleet needs at least one replica",
            ));
        }
        Self::new(
            (0..replicas)
                .map(|i| format!("{name}-{i}.{service}.{namespace}.svc.cluster.local:{port}")),
        )
    }

    /// The addresses, in fleet order.
    pub fn addrs(&self) -> &[String] {
        &self.addrs
    }

    /// The number of servers.
    pub fn len(&self) -> usize {
        self.addrs.len()
    }

    /// Always false: a fleet has at least one server.
    pub fn is_empty(&self) -> bool {
        self.addrs.is_empty()
    }
}

impl FromStr for FleetEndpoints {
    type Err = ClientError;

    fn from_str(list: &str) -> Result<Self> {
        Self::parse(list)
    }
}

/// RFC 1123 label: 1–63 of `[a-z0-9-]`, alphanumeric at both ends.
fn is_dns_label(s: &str) -> bool {
    let bytes = s.as_bytes();
    !bytes.is_empty()
        && bytes.len() <= 63
        && bytes
            .iter()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || *b == b'-')
        && bytes[0] != b'-'
        && bytes[bytes.len() - 1] != b'-'
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stateful_sets_give_one_dns_name_per_pod() {
        let fleet =
            FleetEndpoints::stateful_set("gymfleet", "gymfleet-headless", "rl", 3, 50051).unwrap();
        assert_eq!(
            fleet.addrs(),
            [
                "gymfleet-0.gymfleet-headless.rl.svc.cluster.local:50051",
                "gymfleet-1.gymfleet-headless.rl.svc.cluster.local:50051",
                "gymfleet-2.gymfleet-headless.rl.svc.cluster.local:50051",
            ]
        );
        assert!(FleetEndpoints::stateful_set("gymfleet", "svc", "rl", 0, 1).is_err());
        for bad in ["", "Gymfleet", "gym_fleet", "-gym", "gym-", &"a".repeat(64)] {
            let err = FleetEndpoints::stateful_set(bad, "svc", "rl", 1, 1).unwrap_err();
            assert!(matches!(err, ClientError::Fleet { .. }), "{bad}: {err:?}");
        }
        assert!(FleetEndpoints::stateful_set("a", "b", "NS", 1, 1).is_err());

        let message = |err: ClientError| err.message().to_string();
        assert_eq!(
            message(FleetEndpoints::stateful_set("gymfleet", "svc", "rl", 0, 1).unwrap_err()),
            "a StatefulSet fleet needs at least one replica"
        );
        assert_eq!(
            message(FleetEndpoints::stateful_set("a", "b", "NS", 1, 1).unwrap_err()),
            "namespace name \"NS\": expected a DNS label \
             (1-63 lowercase letters, digits or '-', starting and ending alphanumeric)"
        );
    }

    #[test]
    fn comma_separated_lists_parse() {
        let fleet: FleetEndpoints = " a:1, http://b:2 ,c:3,".parse().unwrap();
        assert_eq!(fleet.addrs(), ["a:1", "http://b:2", "c:3"]);
        assert_eq!(fleet.len(), 3);
        assert!(!fleet.is_empty());
        assert_eq!(FleetEndpoints::parse("a:1").unwrap().addrs(), ["a:1"]);
    }

    #[test]
    fn empty_repeated_and_malformed_lists_are_refused() {
        for bad in ["", " , ,", "a:1,a:1", "a:1,b c:2"] {
            let err = FleetEndpoints::parse(bad).unwrap_err();
            assert!(matches!(err, ClientError::Fleet { .. }), "{bad:?}: {err:?}");
        }
        let err = FleetEndpoints::parse("a:1, a:1").unwrap_err();
        assert!(err.to_string().contains("a:1 is listed twice"), "{err}");
        assert!(FleetEndpoints::new(Vec::<String>::new()).is_err());
        assert!(FleetEndpoints::new([""]).is_err());

        let message = |err: ClientError| err.message().to_string();
        assert_eq!(
            message(FleetEndpoints::parse(" , ,").unwrap_err()),
            "no server endpoints given"
        );
        assert_eq!(
            message(FleetEndpoints::parse("a:1,b c:2").unwrap_err()),
            "endpoint \"b c:2\": expected host:port, http://host:port or unix:/path"
        );
    }
}
