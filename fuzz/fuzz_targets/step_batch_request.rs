#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    gymfleet_fuzz::requests::step_batch_request(data);
});
