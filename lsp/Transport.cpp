#include "lsp/Transport.h"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace moire::lsp {

namespace {

bool startsWithNoCase(std::string_view s, std::string_view prefix) {
    if (s.size() < prefix.size()) return false;
    for (size_t i = 0; i < prefix.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[i])) !=
            std::tolower(static_cast<unsigned char>(prefix[i])))
            return false;
    return true;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

constexpr std::string_view kLengthField = "Content-Length:";

} // namespace

std::optional<Frame> FrameReader::next() {
    if (skip_ > 0) {
        size_t n = std::min(skip_, buffer_.size());
        buffer_.erase(0, n);
        skip_ -= n;
        if (skip_ > 0) return std::nullopt;
    }
    // Blank lines between messages are tolerated (some clients end a body with a newline).
    size_t lead = 0;
    while (lead < buffer_.size() && (buffer_[lead] == '\r' || buffer_[lead] == '\n')) ++lead;
    buffer_.erase(0, lead);
    size_t end = buffer_.find("\r\n\r\n");
    if (end == std::string::npos) {
        if (buffer_.size() <= kMaxHeaderBytes) return std::nullopt;
        resync();
        return Frame{Frame::Kind::BadHeader, {}, "a header longer than 8 KiB, or no header"};
    }
    if (end > kMaxHeaderBytes) {
        resync();
        return Frame{Frame::Kind::BadHeader, {}, "a header longer than 8 KiB"};
    }
    std::string_view header(buffer_.data(), end);
    std::optional<size_t> length;
    std::string error;
    size_t pos = 0;
    while (pos <= header.size() && error.empty()) {
        size_t eol = header.find("\r\n", pos);
        if (eol == std::string_view::npos) eol = header.size();
        std::string_view line = header.substr(pos, eol - pos);
        pos = eol + 2;
        if (startsWithNoCase(line, kLengthField)) {
            std::string_view digits = trim(line.substr(kLengthField.size()));
            size_t n = 0;
            auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
            if (ec != std::errc() || p != digits.data() + digits.size() || digits.empty())
                error = "Content-Length is not a whole number";
            else
                length = n;
        } else if (!startsWithNoCase(line, "Content-Type:")) {
            error = "a header line that is not Content-Length or Content-Type";
        }
    }
    if (error.empty() && !length) error = "no Content-Length";
    if (!error.empty()) {
        resync();
        return Frame{Frame::Kind::BadHeader, {}, error};
    }
    size_t bodyStart = end + 4;
    if (*length > kMaxBodyBytes) {
        size_t have = buffer_.size() - bodyStart;
        skip_ = *length - std::min(have, *length);
        buffer_.erase(0, bodyStart + std::min(have, *length));
        return Frame{Frame::Kind::BadHeader, {}, "a message longer than 256 MiB"};
    }
    if (buffer_.size() - bodyStart < *length) return std::nullopt;
    Frame f{Frame::Kind::Message, buffer_.substr(bodyStart, *length), {}};
    buffer_.erase(0, bodyStart + *length);
    return f;
}

void FrameReader::resync() {
    // The next header is the next Content-Length after this point (a body whose length the
    // bad header did not say is skipped with it).
    for (size_t i = 1; i + kLengthField.size() <= buffer_.size(); ++i)
        if (startsWithNoCase(std::string_view(buffer_).substr(i), kLengthField)) {
            buffer_.erase(0, i);
            return;
        }
    // Keep a tail that may be a Content-Length cut short by the read.
    size_t keep = 0;
    for (size_t k = std::min(buffer_.size(), kLengthField.size() - 1); k > 0 && keep == 0; --k)
        if (startsWithNoCase(kLengthField, std::string_view(buffer_).substr(buffer_.size() - k)))
            keep = k;
    buffer_.erase(0, buffer_.size() - keep);
}

std::string frameMessage(std::string_view body) {
    std::string out = "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n";
    out.append(body);
    return out;
}

} // namespace moire::lsp
