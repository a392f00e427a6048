#include "runtime/serve/StateChannel.h"

namespace moire::serve {

void StateChannel::publish(std::string json) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ++state_.version;
        state_.json = std::move(json);
    }
    changed_.notify_all();
}

std::optional<StateChannel::State> StateChannel::waitNewer(uint64_t seen,
                                                           std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return closed_ || state_.version > seen; });
    if (closed_ || state_.version <= seen) return std::nullopt;
    return state_;
}

void StateChannel::close() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        closed_ = true;
    }
    changed_.notify_all();
}

bool StateChannel::closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
}

StateChannel::State StateChannel::current() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_;
}

} // namespace moire::serve
