//! Where the server listens: a TCP address, or a Unix-domain socket for trainers on the
//! same host (no TCP stack, no loopback checksums: see BENCHMARKS.md).

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use tokio::net::TcpListener;
#[cfg(unix)]
use tokio::net::UnixListener;

/// A listening address: `host:port` or `unix:/path/to/socket` (also `unix:relative/path`
/// and `unix:///absolute/path`, as gRPC names them).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ListenAddr {
    /// A TCP socket address.
    Tcp(std::net::SocketAddr),
    /// The path of a Unix-domain socket.
    Unix(PathBuf),
}

impl FromStr for ListenAddr {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if let Some(path) = s
            .strip_prefix("unix://")
            .or_else(|| s.strip_prefix("unix:"))
        {
            if path.is_empty() {
                return Err("unix: needs a socket path, e.g. unix:/tmp/gymfleet.sock".to_string());
            }
            return Ok(ListenAddr::Unix(PathBuf::from(path)));
        }
        s.parse().map(ListenAddr::Tcp).map_err(|_| {
            format!("expected host:port (e.g. 127.0.0.1:50051) or unix:/path/to/socket, got {s:?}")
        })
    }
}

impl fmt::Display for ListenAddr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ListenAddr::Tcp(addr) => write!(f, "{addr}"),
            ListenAddr::Unix(path) => write!(f, "unix:{}", path.display()),
        }
    }
}

/// A bound listener for [`crate::serve`]: TCP, or a Unix-domain socket whose file is
/// removed when the listener is dropped (when the server stops).
#[derive(Debug)]
pub enum Listener {
    /// A TCP listener.
    Tcp(TcpListener),
    /// A Unix-domain socket listener and its path.
    #[cfg(unix)]
    Unix(UnixListener, SocketFile),
}

impl Listener {
    /// Binds `addr`. A Unix-domain socket replaces a stale socket file left at its path
    /// (by a server that did not stop cleanly), but never any other kind of file.
    pub async fn bind(addr: &ListenAddr) -> std::io::Result<Listener> {
        match addr {
            ListenAddr::Tcp(addr) => Ok(Listener::Tcp(TcpListener::bind(addr).await?)),
            #[cfg(unix)]
            ListenAddr::Unix(path) => {
                remove_stale_socket(path)?;
                let listener = UnixListener::bind(path)?;
                Ok(Listener::Unix(listener, SocketFile(path.clone())))
            }
            #[cfg(not(unix))]
            ListenAddr::Unix(path) => Err(std::io::Error::new(
                std::io::ErrorKind::Unsupported,
                format!("{}: Unix-domain sockets need a Unix system", path.display()),
            )),
        }
    }

    /// The address clients connect to: `host:port` or `unix:/path`.
    pub fn local_addr(&self) -> std::io::Result<ListenAddr> {
        match self {
            Listener::Tcp(listener) => listener.local_addr().map(ListenAddr::Tcp),
            #[cfg(unix)]
            Listener::Unix(_, file) => Ok(ListenAddr::Unix(file.0.clone())),
        }
    }
}

impl From<TcpListener> for Listener {
    fn from(listener: TcpListener) -> Self {
        Listener::Tcp(listener)
    }
}

/// The file of a bound Unix-domain socket, removed on drop.
#[derive(Debug)]
pub struct SocketFile(PathBuf);

impl Drop for SocketFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

#[cfg(unix)]
fn remove_stale_socket(path: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::FileTypeExt;
    match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_socket() => std::fs::remove_file(path),
        Ok(_) => Err(std::io::Error::new(
            std::io::ErrorKind::AlreadyExists,
            format!("{} exists and is not a socket", path.display()),
        )),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_parse_and_print() {
        let tcp: ListenAddr = "127.0.0.1:50051".parse().unwrap();
        assert_eq!(tcp.to_string(), "127.0.0.1:50051");
        for (text, path) in [
            ("unix:/tmp/g.sock", "/tmp/g.sock"),
            ("unix:///tmp/g.sock", "/tmp/g.sock"),
            ("unix:g.sock", "g.sock"),
        ] {
            assert_eq!(
                text.parse::<ListenAddr>().unwrap(),
                ListenAddr::Unix(PathBuf::from(path))
            );
        }
        assert_eq!(
            "unix:/tmp/g.sock"
                .parse::<ListenAddr>()
                .unwrap()
                .to_string(),
            "unix:/tmp/g.sock"
        );
    }

    #[test]
    fn bad_addresses_say_what_is_expected() {
        assert_eq!(
            "localhost".parse::<ListenAddr>().unwrap_err(),
            "expected host:port (e.g. 127.0.0.1:50051) or unix:/path/to/socket, got \"localhost\""
        );
        assert_eq!(
            "unix:".parse::<ListenAddr>().unwrap_err(),
            "unix: needs a socket path, e.g. unix:/tmp/gymfleet.sock"
        );
    }

    #[cfg(unix)]
    #[tokio::test]
    async fn a_unix_socket_replaces_a_stale_one_never_a_file_and_goes_with_its_listener() {
        let dir = std::env::temp_dir().join(format!("gymfleet-listen-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("s.sock");
        let addr = ListenAddr::Unix(path.clone());
        let first = Listener::bind(&addr).await.unwrap();
        // A stale socket (its listener leaked, as after a crash) is replaced.
        std::mem::forget(first);
        let second = Listener::bind(&addr).await.unwrap();
        assert_eq!(second.local_addr().unwrap(), addr);
        drop(second);
        assert!(!path.exists(), "the socket file goes with its listener");

        let file = dir.join("plain");
        std::fs::write(&file, b"data").unwrap();
        let err = Listener::bind(&ListenAddr::Unix(file.clone()))
            .await
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("{} exists and is not a socket", file.display())
        );
        assert_eq!(std::fs::read(&file).unwrap(), b"data");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
