#include "compiler/diag/Suggest.h"

#include <doctest/doctest.h>

using namespace moire;

TEST_CASE("edit distance counts insertions, deletions, substitutions and transpositions") {
    CHECK(editDistance("", "") == 0);
    CHECK(editDistance("sin", "sin") == 0);
    CHECK(editDistance("sinn", "sin") == 1);
    CHECK(editDistance("cso", "cos") == 1);
    CHECK(editDistance("kitten", "sitting") == 3);
    CHECK(editDistance("Theta", "theta") == 0); // case-insensitive
}

TEST_CASE("the nearest name is suggested only when it is close") {
    std::vector<std::string> names = {"spacing", "stroke", "phase", "opacity"};
    CHECK(nearestName("spacng", names) == "spacing");
    CHECK(nearestName("strok", names) == "stroke");
    CHECK(nearestName("zzzzzz", names).empty());
    CHECK(didYouMean("opacty", names).text == "; did you mean 'opacity'?");
    CHECK(didYouMean("opacty", names).replacement == "opacity");
    CHECK(didYouMean("q", names).text.empty());
    CHECK(didYouMean("q", names).replacement.empty());
}

TEST_CASE("a suggestion keeps something of the name written") {
    // Any one-letter name is one edit from any other; suggesting 'e' for 'a' would be noise.
    CHECK(nearestName("a", {"e", "x", "pi"}).empty());
    CHECK(nearestName("X", {"x", "y"}) == "x"); // case alone differs: distance 0
    CHECK(nearestName("sn", {"sin", "t"}) == "sin");
    CHECK(didYouMean("k", {"pi", "e"}).text.empty());
}
