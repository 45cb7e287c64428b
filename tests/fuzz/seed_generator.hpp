#pragma once
// A seed generator of a fuzz target: seed_generator_main.cpp takes the seed folder from the
// command line, creates it and calls write_fuzz_seeds, which each make_<name>_seeds.cpp defines.
#include <filesystem>

/// Writes the target's seed files into `folder` (which exists); false, after saying why on
/// stderr, when one cannot be written.
bool write_fuzz_seeds(const std::filesystem::path& folder);
