// What `facet` does before it starts working: Highway's timer calibration, which libhwy.so runs in
// a static initializer of every process that loads it, must be bound to facet's definition that
// skips it (src/simd/isa.cpp). The dynamic linker's own report of its bindings says which
// definition libhwy's call reaches.
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <string>

#include <hwy/nanobenchmark.h>

#include "simd/isa.hpp"
#include "support/cli.hpp"

namespace {

TEST(Startup, LibhwysTimerCalibrationIsBoundToFacetsDefinition) {
    ::setenv("LD_DEBUG", "bindings", 1);
    const facet_test::CliRun run = facet_test::run_facet({"--help"});
    ::unsetenv("LD_DEBUG");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    std::istringstream lines(run.err);
    std::string binding;
    for (std::string line; std::getline(lines, line);)
        if (line.find("libhwy") != std::string::npos && line.find("_ZN3hwy8platform15TimerResolutionEv") != std::string::npos)
            binding = line;
    ASSERT_FALSE(binding.empty()) << "no binding of hwy::platform::TimerResolution reported";
    // "binding file <libhwy> [0] to <definer> [0]: normal symbol `...'"
    const std::size_t to = binding.find(" to ");
    ASSERT_NE(to, std::string::npos) << binding;
    EXPECT_NE(binding.find(facet_test::facet_binary().filename().string() + " [0]", to), std::string::npos) << binding;
}

TEST(Startup, TheSkippedCalibrationReturnsItsFixedValue) {
    EXPECT_EQ(hwy::platform::TimerResolution(), facet::detail::k_unmeasured_timer_resolution);
}

}  // namespace
