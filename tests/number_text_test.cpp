// numberFromText: the one reading of a number a user wrote (scene attributes, option values, lists).
#include <catch2/catch.hpp>

#include <cmath>

#include "util/number_text.h"

using lt::numberFromText;

TEST_CASE("numberFromText reads what users write and nothing else", "[number_text]") {
    CHECK(numberFromText("0.5") == 0.5);
    CHECK(numberFromText("  -2.5e3 ") == -2500);
    CHECK(numberFromText("+7") == 7);
    CHECK(numberFromText("1E-3") == 1e-3);
    CHECK(numberFromText(".25") == 0.25);
    CHECK(numberFromText("3.") == 3);
    CHECK(std::isinf(*numberFromText("inf")));
    CHECK(std::isnan(*numberFromText("nan")));
    for (const char* bad : {"", " ", "+", "-", "+-1", "++1", "1x", "1 2", "0x10", "1,5", "e5", "1e", "--1", "1e999"})
        CHECK_FALSE(numberFromText(bad));
}
