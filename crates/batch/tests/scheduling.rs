//! The step pool: thread naming, and no deadlock however many callers, pool threads
//! included. (Fairness between batches is tested on the queue itself, in `pool.rs`.)

mod common;

use std::sync::mpsc;
use std::thread;
use std::time::Duration;

use common::*;
use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch, StepPool};

/// Only a watchdog: turns a deadlock into a failure instead of a hung test.
const WATCHDOG: Duration = Duration::from_secs(300);

#[test]
fn threads_are_counted_and_named() {
    let pool = StepPool::new(3).unwrap();
    assert_eq!(pool.threads(), 3);
    let (tx, rx) = mpsc::channel();
    pool.spawn(move || {
        tx.send(thread::current().name().map(str::to_owned))
            .unwrap()
    });
    let name = rx.recv_timeout(WATCHDOG).unwrap().unwrap();
    assert!(name.starts_with("gymfleet-step-"), "{name}");

    let cores = thread::available_parallelism().unwrap().get();
    assert_eq!(StepPool::new(0).unwrap().threads(), cores);
}

#[test]
fn a_panic_in_a_spawned_closure_does_not_take_the_pool_down() {
    let pool = StepPool::new(1).unwrap();
    pool.spawn(|| panic!("deliberate test panic"));
    let (tx, rx) = mpsc::channel();
    pool.spawn(move || tx.send(()).unwrap());
    rx.recv_timeout(WATCHDOG).unwrap();
}

/// Steps a fresh 12-arm batch 10 times; returns the last observations.
fn drive(pool: &StepPool, chunk_size: usize) -> Vec<u32> {
    let mut batch =
        EnvBatch::with_chunk_size(&arm2(4), 12, Autoreset::SameStep, chunk_size).unwrap();
    let mut out = BatchStepOutput::default();
    for t in 0..10 {
        let (action_type, values) = actions(t, 12, 2);
        batch.step(pool, action_type, &values, &mut out).unwrap();
    }
    bits(&out.observations)
}

#[test]
fn many_callers_on_and_off_the_pool_do_not_deadlock() {
    let pool = StepPool::new(2).unwrap();
    let expected = drive(&pool, 12);
    let (tx, rx) = mpsc::channel();
    let mut threads = Vec::new();
    for k in 0..8 {
        // Eight callers on plain threads...
        let (pool_for_thread, tx_thread) = (pool.clone(), tx.clone());
        threads.push(thread::spawn(move || {
            tx_thread.send(drive(&pool_for_thread, 1 + k % 4)).unwrap();
        }));
        // ...and eight inside the pool, more than it has threads.
        let (pool_inside, tx_inside) = (pool.clone(), tx.clone());
        pool.spawn(move || tx_inside.send(drive(&pool_inside, 1 + k % 3)).unwrap());
    }
    drop(tx);
    for _ in 0..16 {
        assert_eq!(
            rx.recv_timeout(WATCHDOG).expect("a caller is stuck"),
            expected
        );
    }
    for t in threads {
        t.join().unwrap();
    }
}

#[test]
fn the_only_pool_thread_can_step_a_batch() {
    let pool = StepPool::new(1).unwrap();
    let expected = drive(&pool, 2);
    let (tx, rx) = mpsc::channel();
    let inner = pool.clone();
    pool.spawn(move || {
        // Nested: a step from inside a step's caller, on a one-thread pool.
        let outer = drive(&inner, 2);
        let nested = drive(&inner, 5);
        tx.send((outer, nested)).unwrap();
    });
    let (outer, nested) = rx.recv_timeout(WATCHDOG).expect("the pool thread is stuck");
    assert_eq!(outer, expected);
    assert_eq!(nested, expected);
}

#[test]
fn batches_and_pools_can_move_between_threads() {
    fn send_static<T: Send + Sync + 'static>() {}
    send_static::<EnvBatch>();
    send_static::<StepPool>();
    send_static::<BatchStepOutput>();
    send_static::<gymfleet_batch::BatchError>();
}
