#include "runtime/output/Parallel.h"

#include <atomic>
#include <doctest/doctest.h>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace moire;

TEST_CASE("forEachInParallel calls every index once, on up to the threads asked for") {
    for (int threads : {0, 1, 2, 5, 100})
        for (int count : {0, 1, 3, 64}) {
            CAPTURE(threads);
            CAPTURE(count);
            std::vector<std::atomic<int>> calls(static_cast<size_t>(count));
            std::mutex m;
            std::set<std::thread::id> ids;
            forEachInParallel(count, threads, [&](int i) {
                calls[static_cast<size_t>(i)].fetch_add(1);
                std::lock_guard<std::mutex> lock(m);
                ids.insert(std::this_thread::get_id());
            });
            for (const auto& c : calls) CHECK(c.load() == 1);
            if (threads > 0) CHECK(static_cast<int>(ids.size()) <= threads);
            if (threads == 1 && count > 0) CHECK(*ids.begin() == std::this_thread::get_id());
        }
}

TEST_CASE("forEachInParallel rethrows the first failure and starts nothing after it") {
    std::atomic<int> started{0};
    CHECK_THROWS_AS(forEachInParallel(1000, 1,
                                      [&](int i) {
                                          started.fetch_add(1);
                                          if (i == 3) throw std::runtime_error("band 3");
                                      }),
                    std::runtime_error);
    CHECK(started.load() == 4);
}
