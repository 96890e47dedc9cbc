#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    gymfleet_fuzz::targets::saved_state_fields(data);
});
