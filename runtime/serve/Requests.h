// The page's messages (JSON bodies of POST requests) read and applied to a Session. Each
// returns the version whose frame shows the change, or throws RequestError with the reason a
// message was refused: not JSON, not an object, a field missing or of the wrong type, a value
// the session refuses. docs/live.md lists the messages.
#pragma once

#include "runtime/serve/Session.h"

#include <string>

namespace moire::serve {

// The largest message body the server reads; a longer one is refused unread (413).
constexpr size_t kMaxMessageBytes = 64 * 1024;

// POST /api/view: {"size": [w, h]}, {"view": "envelope"}, {"overlay": true|false|null},
// {"zoom": {"x": .., "y": .., "factor": ..}}, {"pan": {"from": [x, y], "to": [x, y]}},
// {"reset": true}. One message may carry several; they apply in that order.
uint64_t applyViewMessage(Session& session, const std::string& body);

// POST /api/param: {"name": "drift", "value": 1.5}; the value as ParameterValues.h reads it,
// or null for the parameter's default.
uint64_t applyParameterMessage(Session& session, const std::string& body);

// POST /api/clock: {"play": true}, {"play": false}, {"time": t}; with both, the clock
// stops before it moves, or moves before it starts.
uint64_t applyClockMessage(Session& session, const std::string& body);

} // namespace moire::serve
