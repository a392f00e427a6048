// A test program for tests/skip_status_test.cpp: one case that skips, one that fails after a
// skip, one that passes. Not a test of its own (ctest does not list it).
#include "tests/support/Skip.h"

#include <doctest/doctest.h>

TEST_CASE("probe: skips") {
    moire::test::skip("nothing here to run it on");
    CHECK(1 + 1 == 2);
}

TEST_CASE("probe: fails after a skip") {
    moire::test::skip("nothing here to run it on");
    CHECK(1 + 1 == 3);
}

TEST_CASE("probe: passes") {
    CHECK(1 + 1 == 2);
}
