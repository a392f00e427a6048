// Read into every test's translation unit ahead of its own includes (tests/CMakeLists.txt,
// moire_test_main): doctest prints a `char*` it captures or compares as an address, so a
// case's name captured to say which case failed (CAPTURE(name)) printed as 0x55...; here it
// prints as its text. Comparisons are untouched: two `const char*` still compare as pointers.
#pragma once

#include <doctest/doctest.h>

namespace doctest {

template <>
struct StringMaker<const char*> {
    static String convert(const char* text) { return text ? String(text) : String("nullptr"); }
};
template <>
struct StringMaker<char*> {
    static String convert(const char* text) { return StringMaker<const char*>::convert(text); }
};

} // namespace doctest
