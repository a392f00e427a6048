// The skipped status of tests/support/Skip.h, on a probe program (support/SkipProbe.cpp).
// ctest reports a case as skipped only when it exits with SKIP_RETURN_CODE (77), so a case
// that skips must exit 77 when ctest asks for it, a failed check must still fail, and a run by
// hand (no MOIRE_TEST_SKIP_STATUS) must exit 0 when every check passed.
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire;

namespace {

test::CommandResult probe(const std::string& cases, bool askForStatus) {
    // This program runs under ctest with the variable set: the probe's environment is chosen
    // here, whatever this one's is.
    const std::string env = askForStatus ? std::string("env ") + test::kSkipStatusVariable + "=1 "
                                         : std::string("env -u ") + test::kSkipStatusVariable + " ";
    return test::runCommand(env + MOIRE_SKIP_PROBE + " --no-colors -tc='" + cases + "'");
}

} // namespace

TEST_CASE("skip status: a case that skips exits 77 under ctest, and says why") {
    auto r = probe("probe: skips", true);
    CHECK(r.status == test::kSkipStatus);
    CHECK(r.status == 77); // the SKIP_RETURN_CODE of tests/CMakeLists.txt
    CHECK(r.out.find("skipped: nothing here to run it on") != std::string::npos);
    CHECK(r.err.find("1 part of the tests run were skipped") != std::string::npos);
}

TEST_CASE("skip status: a failed check after a skip still fails") {
    auto r = probe("probe: fails after a skip", true);
    CHECK(r.status == 1);
}

TEST_CASE("skip status: a case that runs whole passes with 0") {
    CHECK(probe("probe: passes", true).status == 0);
}

TEST_CASE("skip status: run by hand, a run with skips that passed exits 0") {
    auto r = probe("probe: skips", false);
    CHECK(r.status == 0);
    CHECK(r.out.find("skipped: nothing here to run it on") != std::string::npos);
    CHECK(probe("probe: fails after a skip", false).status == 1);
}
