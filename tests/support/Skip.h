// Skips that ctest reports as skipped. A test case that cannot run all of itself here (no
// Vulkan device, no X server, a tool not installed, memory limits under AddressSanitizer)
// calls skip() with the reason and goes on with what it can check, or returns. doctest has no
// skip at run time, so the test program counts the calls: when every check passed and some
// part was skipped, it exits with kSkipStatus instead of 0 (tests/support/main.cpp), and
// tests/CMakeLists.txt gives every case that SKIP_RETURN_CODE. A failed check still fails.
#pragma once

#include <string>

namespace moire::test {

// The exit status of a run that passed with a part skipped; 77, as Automake's test driver.
inline constexpr int kSkipStatus = 77;
// Environment variable that asks for kSkipStatus; without it (the test program run by hand,
// all cases at once) a run with skips exits 0 as before and only prints them.
inline constexpr const char* kSkipStatusVariable = "MOIRE_TEST_SKIP_STATUS";

// Prints "skipped: REASON" as a doctest message and counts it for the exit status.
void skip(const std::string& reason);
// How many skip() calls this run made.
int skipCount();
// True, with a skip, under AddressSanitizer: it reserves terabytes of shadow address space
// when a program starts and inflates what it keeps resident, so neither an address-space
// limit nor a peak RSS says anything about moire's own memory there.
bool skipUnderAddressSanitizer();

} // namespace moire::test
