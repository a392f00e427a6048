#include "runtime/serve/StateChannel.h"

#include <doctest/doctest.h>
#include <thread>

using namespace moire::serve;
using namespace std::chrono_literals;

TEST_CASE("state channel: a waiting stream gets the state published after it began waiting") {
    StateChannel channel;
    std::optional<StateChannel::State> got;
    std::thread reader([&] { got = channel.waitNewer(0, 10s); });
    std::this_thread::sleep_for(20ms);
    channel.publish("{\"a\":1}");
    reader.join();
    REQUIRE(got);
    CHECK(got->version == 1);
    CHECK(got->json == "{\"a\":1}");
}

TEST_CASE("state channel: a stream that fell behind gets only the newest state") {
    StateChannel channel;
    for (int i = 0; i < 1000; ++i) channel.publish(std::to_string(i));
    std::optional<StateChannel::State> got = channel.waitNewer(0, 0ms);
    REQUIRE(got);
    CHECK(got->version == 1000);
    CHECK(got->json == "999");
    // Seen it: nothing newer until the next publish.
    CHECK_FALSE(channel.waitNewer(got->version, 10ms));
}

TEST_CASE("state channel: closing wakes the waiting streams with nothing") {
    StateChannel channel;
    channel.publish("x");
    std::optional<StateChannel::State> got = StateChannel::State{};
    std::thread reader([&] { got = channel.waitNewer(1, 10s); });
    std::this_thread::sleep_for(20ms);
    channel.close();
    reader.join();
    CHECK_FALSE(got);
    CHECK(channel.closed());
    CHECK_FALSE(channel.waitNewer(0, 10ms)); // closed: nothing even though version 1 is newer
}
