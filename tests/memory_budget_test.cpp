// Checking an allocation against the memory available (libpath/math/memory_budget.h).
#include <catch2/catch.hpp>

#include "math/memory_budget.h"
#include "test_util.h"

using namespace lt;

TEST_CASE("requireMemory refuses what cannot fit, naming it, and lets ordinary sizes through", "[memory]") {
    const uint64_t available = availableMemory();
    REQUIRE(available > 0); // /proc/meminfo on Linux
    CHECK(test::errorOf([] { requireMemory(1 << 20, "a megabyte"); }) == "(no error)");
    const std::string tooMuch = test::errorOf([&] { requireMemory(4.0 * double(available), "a huge film"); });
    CHECK_THAT(tooMuch, Catch::StartsWith("a huge film needs ") && Catch::Contains(" GiB of memory, more than the ") &&
                            Catch::EndsWith(" GiB available"));
    // Products of sizes beyond 2^64 bytes stay a clear error.
    CHECK_THAT(test::errorOf([] { requireMemory(1e30, "1e30 bytes"); }), Catch::StartsWith("1e30 bytes needs "));
}
