#include "runtime/serve/Token.h"

#include <cstdint>
#include <random>

namespace moire::serve {

std::string makeToken() {
    std::random_device device;
    static constexpr char kHex[] = "0123456789abcdef";
    std::string token;
    for (int word = 0; word < 4; ++word) {
        uint32_t bits = device(); // random_device gives 32 bits a call
        for (int nibble = 0; nibble < 8; ++nibble, bits >>= 4) token += kHex[bits & 0xf];
    }
    return token;
}

bool sameToken(std::string_view given, std::string_view token) {
    if (given.size() != token.size() || token.empty()) return false;
    unsigned char diff = 0;
    for (size_t i = 0; i < token.size(); ++i)
        diff |= static_cast<unsigned char>(given[i] ^ token[i]);
    return diff == 0;
}

} // namespace moire::serve
