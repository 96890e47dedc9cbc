//! The connection's unit tests: per-call deadlines, and what connecting fails with.

use super::*;

fn grpc_timeout(metadata: &CallMetadata) -> Option<String> {
    let request = metadata.clone().call(Request::new(())).unwrap();
    request
        .metadata()
        .get("grpc-timeout")
        .map(|v| v.to_str().unwrap().to_string())
}

#[tokio::test]
async fn a_token_that_is_not_printable_ascii_is_refused_by_both_transports() {
    let message = |err: ClientError| err.to_string();
    let bad = || {
        Client::builder("127.0.0.1:1")
            .token("bad\ntoken")
            .lazy(true)
    };
    let over_network = message(bad().connect().await.unwrap_err());
    // Any service does: the token is refused before it is used.
    let service = tower::service_fn(
        |_: tonic::codegen::http::Request<tonic::body::Body>| async {
            Ok::<_, std::convert::Infallible>(tonic::codegen::http::Response::new(
                tonic::body::Body::empty(),
            ))
        },
    );
    let in_process = message(bad().in_process(service).unwrap_err());
    assert_eq!(over_network, in_process);
    assert!(
        in_process.contains("the token must be printable ASCII without spaces"),
        "{in_process}"
    );
    assert!(in_process.contains("127.0.0.1:1"), "{in_process}");
}

#[tokio::test]
async fn deadlines_go_out_as_grpc_timeout_the_earlier_winning() {
    let none = CallMetadata::default();
    assert_eq!(grpc_timeout(&none), None);
    let builder = CallMetadata(Arc::new(CallSettings {
        authorization: None,
        deadline: Some(Duration::from_secs(30)),
    }));
    assert_eq!(grpc_timeout(&builder).as_deref(), Some("30000000u"));
    let scoped = with_deadline(Duration::from_millis(200), async {
        (grpc_timeout(&none), grpc_timeout(&builder))
    })
    .await;
    for got in [scoped.0, scoped.1] {
        let micros: u64 = got.unwrap().trim_end_matches('u').parse().unwrap();
        assert!((150_000..=200_000).contains(&micros), "{micros}");
    }
}

#[tokio::test]
async fn unreachable_servers_are_connect_errors() {
    // A port that was just free: nothing listens on it.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    drop(listener);
    let err = Client::connect(addr.clone()).await.unwrap_err();
    let ClientError::Connect { addr: a, reason } = &err else {
        panic!("{err:?}");
    };
    assert_eq!(*a, addr);
    assert!(reason.contains("refused"), "{reason}");
    assert!(
        !reason.contains("tcp connect error: tcp connect error"),
        "each cause once: {reason}"
    );
    assert_eq!(
        err.to_string(),
        format!(
            "cannot connect to the gymfleet server at {addr}: {reason}. Is the server \
             running? To use another one, pass its address to Client::connect (a fleet: \
             its FleetEndpoints)."
        )
    );
    // A malformed address is the caller's setting, not a server that is down.
    let err = Client::connect("http://[not an address").await.unwrap_err();
    assert!(matches!(err, ClientError::Setting { .. }), "{err:?}");
    assert!(
        err.to_string()
            .starts_with("cannot connect to http://[not an address: "),
        "{err}"
    );
    assert!(!err.to_string().contains("running"), "{err}");
}
