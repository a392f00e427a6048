#include "tests/support/Skip.h"

#include <atomic>
#include <doctest/doctest.h>

namespace moire::test {

namespace {
std::atomic<int> skips{0};
} // namespace

void skip(const std::string& reason) {
    MESSAGE("skipped: ", reason);
    ++skips;
}

int skipCount() {
    return skips.load();
}

bool skipUnderAddressSanitizer() {
#ifdef __SANITIZE_ADDRESS__
    skip("memory limits are not measurable under AddressSanitizer");
    return true;
#else
    return false;
#endif
}

} // namespace moire::test
