// Checking an allocation against the memory available (libpath/util/memory_budget.h).
#include <catch2/catch.hpp>

#include "util/memory_budget.h"
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

TEST_CASE("LT_MEMORY_LIMIT lowers the memory lt counts on, and a malformed one is an error", "[memory]") {
    const uint64_t machine = availableMemory();
    REQUIRE(machine > (uint64_t(1) << 30));
    struct Restore {
        ~Restore() { unsetenv("LT_MEMORY_LIMIT"); }
    } restore;
    setenv("LT_MEMORY_LIMIT", "64M", 1);
    CHECK(availableMemory() == 64 * (uint64_t(1) << 20));
    CHECK_THAT(test::errorOf([] { requireMemory(100e6, "a 100 MB film"); }),
               Catch::Equals("a 100 MB film needs 95 MiB of memory, more than the 64 MiB available"));
    CHECK(test::errorOf([] { requireMemory(50e6, "a 50 MB film"); }) == "(no error)");
    setenv("LT_MEMORY_LIMIT", "1000000", 1);
    CHECK(availableMemory() == 1000000);
    setenv("LT_MEMORY_LIMIT", "0.5g", 1);
    CHECK(availableMemory() == uint64_t(1) << 29);
    // A limit above what the machine has changes nothing.
    setenv("LT_MEMORY_LIMIT", "1000T", 1);
    CHECK(availableMemory() <= machine + (uint64_t(1) << 30)); // MemAvailable moves a little between reads
    setenv("LT_MEMORY_LIMIT", " 2K ", 1);
    CHECK(availableMemory() == 2048);
    CHECK(test::errorOf([] { requireMemory(3000, "3000 bytes"); }) ==
          "3000 bytes needs 3 KiB of memory, more than the 2 KiB available");
    setenv("LT_MEMORY_LIMIT", "100", 1);
    CHECK(test::errorOf([] { requireMemory(101, "101 bytes"); }) ==
          "101 bytes needs 101 bytes of memory, more than the 100 bytes available");
    // Under one byte would read as "unknown" and turn the checks off: refused.
    for (const char* bad : {"lots", "-1G", "0", "0.5", "4GB", "G", "nan", "1e300T", ""}) {
        if (!*bad) continue; // unset: no limit, tested above by the machine's figure

        setenv("LT_MEMORY_LIMIT", bad, 1);
        CHECK(test::errorOf([] { (void)availableMemory(); }) ==
              "LT_MEMORY_LIMIT: '" + std::string(bad) + "' is not a memory size such as 4G, 512M or 1000000");
    }
}
