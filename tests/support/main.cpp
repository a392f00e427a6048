// The test programs' main: doctest's, and the skipped status of tests/support/Skip.h.
#define DOCTEST_CONFIG_IMPLEMENT
#include "tests/support/Skip.h"

#include <cstdio>
#include <cstdlib>
#include <doctest/doctest.h>

int main(int argc, char** argv) {
    doctest::Context context(argc, argv);
    const int status = context.run();
    if (context.shouldExit() || status != 0) return status;
    const int skipped = moire::test::skipCount();
    if (skipped == 0) return 0;
    std::fprintf(stderr, "%d part%s of the tests run were skipped (see the messages above)\n",
                 skipped, skipped == 1 ? "" : "s");
    return std::getenv(moire::test::kSkipStatusVariable) ? moire::test::kSkipStatus : 0;
}
