#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    gymfleet_fuzz::targets::assets_archive(data);
});
