//! The models the env benchmarks run: the seed models, the 6-DOF arm and the 20-link chain,
//! each with the instance it observes.
#![allow(dead_code, unreachable_pub)]

pub const PENDULUM: &str = include_str!("../../../../models/pendulum.json");
pub const ARM2: &str = include_str!("../../../../models/arm2.json");
pub const ARM6: &str = include_str!("../../../../models/arm6.json");
pub const CHAIN20: &str = include_str!("../../../../models/chain20.json");

/// `(name, document, end effector)`.
pub const MODELS: [(&str, &str, &str); 4] = [
    ("pendulum", PENDULUM, "arm"),
    ("arm2", ARM2, "forearm"),
    ("arm6", ARM6, "tool"),
    ("chain20", CHAIN20, "link20"),
];
