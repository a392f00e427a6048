// The base protocol's framing: each message is a header block (`Content-Length: N`, maybe a
// `Content-Type`, each line ended by CRLF, the block by an empty line) and then N bytes of
// JSON. The reader is fed bytes as they arrive and hands back whole bodies, or says that a
// header was malformed and where it picked the stream up again; it never blocks and never
// reads, so it is tested without a pipe (the server's loop does the reading).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace moire::lsp {

// The longest header block and body accepted. A longer header is malformed; a longer body
// is refused (its bytes skipped) rather than held in memory.
constexpr size_t kMaxHeaderBytes = 8 * 1024;
constexpr size_t kMaxBodyBytes = 256u * 1024 * 1024;

struct Frame {
    enum class Kind { Message, BadHeader } kind;
    std::string body;  // Message: the JSON text
    std::string error; // BadHeader: what was wrong with it
};

class FrameReader {
  public:
    void feed(std::string_view bytes) { buffer_.append(bytes); }
    // The next whole frame, or nothing until more bytes come.
    std::optional<Frame> next();
    // Bytes held that do not yet make a frame.
    size_t pending() const { return buffer_.size(); }

  private:
    // After a malformed header: drops bytes up to the next line that starts a header.
    void resync();

    std::string buffer_;
    size_t skip_ = 0; // body bytes of a refused message still to drop
};

// `body` framed for the wire.
std::string frameMessage(std::string_view body);

} // namespace moire::lsp
