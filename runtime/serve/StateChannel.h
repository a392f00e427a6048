// The page's view of the session, handed from whoever changes it (the reload thread, the
// render thread, a request) to the event streams that send it (server-sent events). Only the
// newest state is kept: a stream that falls behind skips the states between, so a burst of
// changes (a thousand slider messages a second) never queues a thousand messages.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

namespace moire::serve {

class StateChannel {
  public:
    struct State {
        uint64_t version = 0; // increases with every publish()
        std::string json;
    };

    // Replaces the state and wakes every waiting stream.
    void publish(std::string json);
    // The state once its version is above `seen`: at once when it already is, else when a
    // publish() makes it so. Nothing when `timeout` passes first or the channel is closed.
    std::optional<State> waitNewer(uint64_t seen, std::chrono::milliseconds timeout);
    // Wakes every stream for good: the server is stopping.
    void close();
    bool closed() const;
    State current() const;

  private:
    mutable std::mutex mutex_;
    std::condition_variable changed_;
    State state_;
    bool closed_ = false;
};

} // namespace moire::serve
