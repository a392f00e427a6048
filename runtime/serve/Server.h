// The HTTP side of `moire serve` (cpp-httplib): the page, its messages, the event stream of
// the session's state (server-sent events), and the frames as PNG files fetched by id.
//
// Every request must carry the run's token (`?token=` or the X-Moire-Token header), or it is
// refused with 403 before it reaches a handler. Nothing is read from disk: the page is
// compiled in (PageFiles.h) and the frames live in memory. Bodies above kMaxMessageBytes are
// refused unread (413), malformed HTTP is answered 400 by the library, and a message the
// session refuses is answered 400 with {"error": "..."}: none of them stops the server.
#pragma once

#include "runtime/serve/Session.h"

#include <atomic>
#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace moire::serve {

// Event streams open at once; a further one is refused (503) so that they cannot take every
// one of the server's threads.
constexpr int kMaxEventStreams = 4;

class Server {
  public:
    Server(Session& session, std::string token);
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    // Binds `host` (an address) at `port` (0: any free port) and returns the port. Throws
    // std::runtime_error with the reason when it cannot.
    int bind(const std::string& host, int port);
    // Serves on a thread of its own until stop().
    void start();
    void stop();

    const std::string& token() const { return token_; }
    // The page's address: http://HOST:PORT/?token=TOKEN.
    std::string url(const std::string& host, int port) const;

  private:
    void routes();

    Session& session_;
    std::string token_;
    std::unique_ptr<httplib::Server> http_;
    std::atomic<int> streams_{0};
    std::thread thread_;
};

} // namespace moire::serve
