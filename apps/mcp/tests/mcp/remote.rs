//! The adapter as a client of servers the test started itself (`--server`): envs land on
//! those servers, several servers share the load, and what the adapter created is closed
//! when its client goes away.

use serde_json::json;

use crate::{doc, Adapter, TestServer, ARM2, PENDULUM};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn envs_live_on_the_given_server_and_are_closed_at_exit() {
    let server = TestServer::start().await;
    let addr = server.addr();
    let adapter = Adapter::spawn(&["--server", &addr]).await;
    let created = adapter
        .ok(
            "create_robot_env",
            json!({"document": doc(PENDULUM), "end_effector_ids": ["arm"]}),
        )
        .await;
    assert_eq!(created["env_id"], "sim_1");
    adapter
        .ok(
            "batch_create_envs",
            json!({"document": doc(ARM2), "n_envs": 4}),
        )
        .await;
    assert_eq!(server.held().await, (1, 4));
    adapter.ok("gym_reset", json!({"env_id": "sim_1"})).await;
    adapter
        .ok(
            "gym_step",
            json!({"env_id": "sim_1", "action_type": "velocity", "values": [10]}),
        )
        .await;

    // Closing stdin ends the session; the adapter closes what it created on the way out.
    adapter.stop().await;
    assert_eq!(server.held().await, (0, 0));
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn several_servers_share_new_envs_without_id_clashes() {
    let (a, b) = (TestServer::start().await, TestServer::start().await);
    let servers = format!("{},{}", a.addr(), b.addr());
    let adapter = Adapter::spawn(&["--server", &servers]).await;
    let args = json!({"document": doc(PENDULUM), "end_effector_ids": ["arm"]});
    for n in 1..=4 {
        let created = adapter.ok("create_robot_env", args.clone()).await;
        assert_eq!(created["env_id"], format!("sim_{n}"));
    }
    assert_eq!(a.held().await, (2, 0));
    assert_eq!(b.held().await, (2, 0));
    // Each adapter id reaches its own env, wherever it lives.
    for n in 1..=4 {
        let env_id = format!("sim_{n}");
        adapter.ok("gym_reset", json!({"env_id": env_id})).await;
        adapter
            .ok(
                "gym_step",
                json!({"env_id": env_id, "action_type": "torque", "values": [n]}),
            )
            .await;
    }
    adapter.ok("gym_close", json!({"env_id": "sim_1"})).await;
    adapter.ok("gym_close", json!({"env_id": "sim_2"})).await;
    assert_eq!((a.held().await, b.held().await), ((1, 0), (1, 0)));

    // A server that went away: calls on its envs say where they lived.
    let (a_addr, b_addr) = (a.addr(), b.addr());
    a.stop().await;
    let mut down = 0;
    for env_id in ["sim_3", "sim_4"] {
        let result = adapter.call("gym_observe", json!({"env_id": env_id})).await;
        if result.is_error == Some(true) {
            let err = crate::expect_err("gym_observe", result);
            assert!(
                err.contains(&a_addr) && err.contains("Is the server running?"),
                "{err} (servers {a_addr}, {b_addr})"
            );
            assert!(err.contains(&format!("env_id \"{env_id}\"")), "{err}");
            down += 1;
        }
    }
    assert_eq!(
        down, 1,
        "exactly one remaining env lived on the stopped server"
    );
    adapter.stop().await;
    assert_eq!(b.held().await, (0, 0));
    b.stop().await;
}
