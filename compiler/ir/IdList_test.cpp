// IdList against std::vector: the same random sequence of operations on both, compared after
// each step, across the switch from inline storage to the heap and back.
#include "compiler/ir/IdList.h"

#include <doctest/doctest.h>
#include <random>
#include <utility>
#include <vector>

using moire::ir::IdList;

namespace {

bool same(const IdList& a, const std::vector<uint32_t>& b) {
    if (a.size() != b.size() || a.empty() != b.empty()) return false;
    for (size_t i = 0; i < b.size(); ++i)
        if (a[i] != b[i]) return false;
    return std::vector<uint32_t>(a) == b;
}

} // namespace

TEST_CASE("IdList: random operations agree with std::vector") {
    std::mt19937 rng(12345);
    for (int trial = 0; trial < 200; ++trial) {
        IdList a;
        std::vector<uint32_t> b;
        for (int step = 0; step < 60; ++step) {
            uint32_t v = rng() % 1000;
            switch (rng() % 9) {
            case 0:
            case 1:
            case 2:
                a.push_back(v);
                b.push_back(v);
                break;
            case 3:
                if (!b.empty()) {
                    a.pop_back();
                    b.pop_back();
                }
                break;
            case 4: {
                size_t n = rng() % 9;
                a.assign(n, v);
                b.assign(n, v);
                break;
            }
            case 5: { // copy, then the copy grows on its own
                IdList c = a;
                c.push_back(v);
                std::vector<uint32_t> d = b;
                d.push_back(v);
                REQUIRE(same(c, d));
                a = c;
                b = d;
                break;
            }
            case 6: { // move out and back
                IdList c = std::move(a);
                CHECK(a.empty());
                a = std::move(c);
                break;
            }
            case 7: {
                std::vector<uint32_t> d(rng() % 7, v);
                a = d;
                b = d;
                break;
            }
            case 8:
                if (rng() % 4 == 0) {
                    a.clear();
                    b.clear();
                } else {
                    a.reserve(rng() % 10);
                }
                break;
            }
            REQUIRE(same(a, b));
            if (!b.empty()) {
                CHECK(a.back() == b.back());
                CHECK(a.front() == b.front());
                CHECK(*a.rbegin() == *b.rbegin());
            }
        }
    }
}

TEST_CASE("IdList: construction, comparison and bounds") {
    IdList a{1, 2, 3, 4, 5};
    CHECK(a.size() == 5);
    IdList b(std::vector<uint32_t>{1, 2, 3, 4, 5});
    CHECK(a == b);
    b.back() = 6;
    CHECK(!(a == b));
    CHECK_THROWS_AS(a.at(5), std::out_of_range);
    IdList c{7};
    c = {8, 9};
    CHECK(c == IdList{8, 9});
    IdList& self = c;
    c = self;
    CHECK(c == IdList{8, 9});
}
