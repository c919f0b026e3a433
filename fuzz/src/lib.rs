//! The interpreter behind the fuzz targets, kept free of libFuzzer so that the stable test
//! `tests/fuzz_corpus.rs` of the main crate can replay the committed corpus through it.
pub mod api;
