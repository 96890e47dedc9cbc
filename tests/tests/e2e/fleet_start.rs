//! A fleet that starts with a server down (`Fleet::connect_available`): placed on the
//! servers that answer, taking the others in when they do; the default (`Fleet::connect`)
//! still needs every server.

use gymfleet_client::{ActionType, BatchOptions, ClientError, EnvOptions, Fleet, FleetEndpoints};
use gymfleet_e2e::{TestServer, ARM2};
use gymfleet_server::ServerConfig;

/// A loopback port nothing listens on (it was free a moment ago).
fn free_port() -> std::net::SocketAddr {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    listener.local_addr().expect("address")
}

fn one_thread() -> ServerConfig {
    ServerConfig {
        threads: 1,
        ..ServerConfig::default()
    }
}

fn arms(n_envs: usize) -> BatchOptions {
    BatchOptions::new(ARM2, n_envs)
        .end_effectors(["forearm"])
        .seed(5)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_fleet_can_start_with_a_server_down_and_takes_it_in_when_it_answers() {
    let up = TestServer::start(one_thread()).await;
    let down = free_port();
    let (up_addr, down_addr) = (up.addr().to_string(), down.to_string());
    let endpoints = FleetEndpoints::new([up_addr.clone(), down_addr.clone()]).expect("endpoints");

    // The default needs every server, and names the one missing.
    let err = Fleet::connect(endpoints.clone()).await.unwrap_err();
    assert!(
        matches!(&err, ClientError::Connect { addr, .. } if *addr == down_addr),
        "{err:?}"
    );

    let fleet = Fleet::connect_available(endpoints)
        .await
        .expect("one server answers");
    assert!(fleet.places_on_answering_servers());
    assert_eq!(fleet.servers(), [up_addr.as_str(), down_addr.as_str()]);
    let mut early = fleet.create_batch(arms(6)).await.expect("placed on one");
    let placed: Vec<_> = early
        .placement()
        .into_iter()
        .map(|s| (s.server, s.envs))
        .collect();
    assert_eq!(placed, [(up_addr.clone(), 0..6)]);
    let env = fleet.create_env(EnvOptions::new(ARM2)).await.expect("env");
    assert_eq!(env.server(), up_addr);

    // The second server comes up at its address: the next batch is split over both, and
    // its envs step bitwise as the first batch's.
    let late = TestServer::start_at(down, one_thread()).await;
    let mut both = fleet.create_batch(arms(6)).await.expect("placed on both");
    let placed: Vec<_> = both
        .placement()
        .into_iter()
        .map(|s| (s.server, s.envs))
        .collect();
    assert_eq!(placed, [(up_addr.clone(), 0..3), (down_addr.clone(), 3..6)]);
    early.reset(Some(5)).await.expect("reset");
    both.reset(Some(5)).await.expect("reset");
    let actions = vec![0.01_f32; 6 * early.info().action_dim];
    for _ in 0..10 {
        let a = early
            .step(ActionType::Torque, &actions)
            .await
            .expect("step");
        let b = both.step(ActionType::Torque, &actions).await.expect("step");
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a.observations()), bits(b.observations()));
    }
    early.close().await.expect("close");
    both.close().await.expect("close");
    drop((up, late));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_fleet_with_no_server_answering_says_so_for_each() {
    let (a, b) = (free_port().to_string(), free_port().to_string());
    let endpoints = FleetEndpoints::new([a.clone(), b.clone()]).expect("endpoints");
    let Err(ClientError::Fleet { message }) = Fleet::connect_available(endpoints).await else {
        panic!("no server answers");
    };
    assert!(
        message.starts_with(&format!(
            "no server of the fleet answered: cannot connect to the gymfleet server at {a}: "
        )),
        "{message}"
    );
    assert!(
        message.contains(&format!(
            " | cannot connect to the gymfleet server at {b}: "
        )),
        "{message}"
    );
}
