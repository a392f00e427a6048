// The serve session without HTTP: its frames are what a render of the scene draws, a bad save
// keeps the last picture under located diagnostics, the page's zoom is the scene's camera zoom,
// and a burst of changes is drawn once, at its newest.
#include "compiler/backend/llvm/LlvmJit.h"
#include "runtime/output/ImageIO.h"
#include "runtime/serve/Requests.h"
#include "runtime/serve/Session.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

namespace moire::serve {
namespace {

using json = nlohmann::json;

std::string scene(double zoom, double spacing) {
    return "scene { size = (96, 64); background = #f0ece4 }\n"
           "camera { zoom = " +
           std::to_string(zoom) +
           " }\n"
           "layer a { family = circles; spacing = " +
           std::to_string(spacing) +
           "; stroke = 1.2; color = #202028; origin = (-3, 0) }\n"
           "layer b { family = lines; spacing = 4; rotation = 12deg; stroke = 1 }\n";
}

// Waits (up to 30 s) until the state satisfies `done`, and returns it.
template <class Done>
json waitState(Session& session, Done done) {
    for (int i = 0; i < 3000; ++i) {
        json s = json::parse(session.stateJson());
        if (done(s)) return s;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    FAIL("timed out waiting for the session");
    return {};
}

json waitShown(Session& session, uint64_t version) {
    return waitState(session, [&](const json& s) {
        return s["shownVersion"].get<uint64_t>() >= version && !s["frame"].is_null();
    });
}

// The session's frame `id` as 8-bit RGBA, as a PNG read back through OpenImageIO; the same
// as the bytes the page takes.
std::vector<uint8_t> framePixels(Session& session, uint64_t id, const test::TempDir& dir) {
    auto png = session.framePng(id);
    REQUIRE(png);
    const std::string path = dir.file("frame.png");
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(png->data()),
               static_cast<std::streamsize>(png->size()));
    Image img = readImage(path);
    std::vector<uint8_t> out;
    for (size_t i = 0; i < static_cast<size_t>(img.width) * img.height; ++i)
        for (int c = 0; c < 4; ++c) out.push_back(toByte(img.pixels[i * img.channels + c]));
    std::optional<Session::Frame> raw = session.frame(id);
    REQUIRE(raw);
    CHECK(*raw->rgba == out);
    return out;
}

// `text` rendered in the render mode (no view slots), as 8-bit RGBA: the oracle.
std::vector<uint8_t> rendered(const std::string& text, int w, int h) {
    std::unique_ptr<SceneProgram> program = test::compileOk(text);
    LlvmJitBackend jit;
    Image img = test::renderScene(*program, jit, w, h);
    std::vector<uint8_t> out;
    for (size_t i = 0; i < static_cast<size_t>(img.width) * img.height; ++i)
        for (int c = 0; c < 4; ++c) out.push_back(toByte(img.pixels[i * img.channels + c]));
    return out;
}

// A session on `text`, saved as s.moire in a folder of its own, its clock stopped at 0.
struct Served {
    explicit Served(const std::string& text) {
        dir.write("s.moire", text);
        SessionOptions o;
        o.scene = dir.file("s.moire");
        o.paused = true;
        o.threads = 2;
        o.watch.debounce = std::chrono::milliseconds(5);
        session = std::make_unique<Session>(jit, o);
        REQUIRE(session->start().good());
    }
    ~Served() { session->stop(); }

    test::TempDir dir{"serve-session"};
    LlvmJitBackend jit;
    std::unique_ptr<Session> session;
};

} // namespace

TEST_CASE("serve session: frames are the render's pixels, and a bad save keeps the picture") {
    Served served(scene(1.5, 5));
    Session& session = *served.session;
    const test::TempDir& dir = served.dir;

    json s = waitShown(session, 1);
    CHECK(s["frame"]["width"] == 96);
    CHECK(s["frame"]["height"] == 64);
    const uint64_t firstId = s["frame"]["id"];
    CHECK(framePixels(session, firstId, dir) == rendered(scene(1.5, 5), 96, 64));

    // The page's size, then a bad save: located diagnostics, the same picture.
    const uint64_t sized = session.resize(120, 50);
    s = waitShown(session, sized);
    const uint64_t sizedId = s["frame"]["id"];
    CHECK(framePixels(session, sizedId, dir) == rendered(scene(1.5, 5), 120, 50));
    dir.write("s.moire", "scene { size = (96, 64) }\nlayer a { family = circles; spacing = }\n");
    s = waitState(session, [](const json& s) { return !s["errors"].get<std::string>().empty(); });
    CHECK(s["errors"].get<std::string>().find("s.moire:2:") != std::string::npos);
    CHECK(s["frame"]["id"] == sizedId);
    CHECK(session.frame(sizedId));

    // The fix: diagnostics gone, the new text's picture.
    dir.write("s.moire", scene(1.5, 7));
    s = waitState(session, [&](const json& s) {
        return s["errors"] == "" && s["frame"]["id"].get<uint64_t>() != sizedId &&
               s["shownVersion"] == s["version"];
    });
    CHECK(framePixels(session, s["frame"]["id"], dir) == rendered(scene(1.5, 7), 120, 50));
}

TEST_CASE("serve session: zooming about the centre is the scene's camera zoomed") {
    Served served(scene(1.5, 5));
    Session& session = *served.session;
    const test::TempDir& dir = served.dir;
    waitShown(session, 1);
    // Pixel centres are at i + 0.5: the frame's centre is (48, 32).
    const uint64_t v = applyViewMessage(session, R"({"zoom": {"x": 48, "y": 32, "factor": 2}})");
    json s = waitShown(session, v);
    CHECK(s["zoom"] == doctest::Approx(2.0));
    // An independent oracle: the scene with its own zoom doubled. Float pixels may round the
    // other way where the two multiply in another order: a few, by one level.
    std::vector<uint8_t> got = framePixels(session, s["frame"]["id"], dir);
    std::vector<uint8_t> want = rendered(scene(3.0, 5), 96, 64);
    REQUIRE(got.size() == want.size());
    int off = 0;
    for (size_t i = 0; i < got.size(); ++i) off += std::abs(got[i] - want[i]) > 1;
    CHECK(off == 0);

    // Back to the scene's camera.
    s = waitShown(session, applyViewMessage(session, R"({"reset": true})"));
    CHECK(framePixels(session, s["frame"]["id"], dir) == rendered(scene(1.5, 5), 96, 64));
}

TEST_CASE("serve session: a burst of changes is drawn once more at most, at its newest") {
    Served served(scene(1.5, 5));
    Session& session = *served.session;
    json s = waitShown(session, 1);
    const uint64_t before = s["frame"]["id"];
    uint64_t last = 0;
    for (int i = 0; i < 500; ++i) last = session.pan(10, 10, 10.5, 10);
    s = waitShown(session, last);
    CHECK(s["shownVersion"] == last);
    // Each frame takes the newest job: far fewer frames than changes.
    CHECK(s["frame"]["id"].get<uint64_t>() - before < 500);
}

TEST_CASE("serve session: a slider's value draws the scene written with it, and compiles nothing") {
    auto text = [](const char* gap) {
        return std::string("param gap = ") + gap +
               " in 3 .. 9 step 0.5\n"
               "scene { size = (96, 64); background = #f0ece4 }\n"
               "layer a { family = circles; spacing = gap; stroke = 1.2; origin = (-3, 0) }\n"
               "layer b { family = lines; spacing = gap * 0.75; rotation = 12deg; stroke = 1 }\n";
    };
    Served served(text("5"));
    Session& session = *served.session;
    const test::TempDir& dir = served.dir;
    LlvmJitBackend& jit = served.jit;
    json s = waitShown(session, 1);
    REQUIRE(s["params"].size() == 1);
    CHECK(s["params"][0]["name"] == "gap");
    CHECK(s["params"][0]["min"] == 3.0);
    CHECK(s["params"][0]["max"] == 9.0);
    CHECK(s["params"][0]["step"] == 0.5);
    CHECK(s["params"][0]["value"] == json::array({5.0}));
    CHECK(s["params"][0]["set"] == false);
    const int compiles = jit.compileCount();

    s = waitShown(session, applyParameterMessage(session, R"({"name": "gap", "value": 7.5})"));
    CHECK(framePixels(session, s["frame"]["id"], dir) == rendered(text("7.5"), 96, 64));
    CHECK(s["params"][0]["value"] == json::array({7.5}));
    CHECK(s["params"][0]["set"] == true);
    CHECK(jit.compileCount() == compiles);

    // Refused: nothing changes.
    const uint64_t v = session.version();
    for (const char* body : {R"({"name": "gape", "value": 4})", R"({"name": "gap", "value": 9.5})",
                             R"({"name": "gap", "value": true})", R"({"name": "gap"})"}) {
        CAPTURE(std::string(body));
        CHECK_THROWS_AS(applyParameterMessage(session, body), RequestError);
    }
    try {
        applyParameterMessage(session, R"({"name": "gape", "value": 4})");
    } catch (const RequestError& e) {
        CHECK(std::string(e.what()) == "unknown parameter 'gape': the scene's are gap");
    }
    CHECK(session.version() == v);

    // The value outlives a save that keeps the parameter; null gives back the default.
    dir.write("s.moire", text("4"));
    s = waitState(session, [&](const json& s) {
        return s["version"].get<uint64_t>() > v && s["shownVersion"] == s["version"];
    });
    CHECK(framePixels(session, s["frame"]["id"], dir) == rendered(text("7.5"), 96, 64));
    s = waitShown(session, applyParameterMessage(session, R"({"name": "gap", "value": null})"));
    CHECK(framePixels(session, s["frame"]["id"], dir) == rendered(text("4"), 96, 64));
    CHECK(jit.compileCount() == compiles);
}

TEST_CASE("serve messages: refused with the reason, and nothing changes") {
    Served served(scene(1.5, 5));
    Session& session = *served.session;
    const uint64_t v = session.version();
    const std::pair<const char*, const char*> refused[] = {
        {"", "not JSON"},
        {"3", "JSON object"},
        {R"({"size": [1, 99999]})", "size[1]"},
        {R"({"view": "upside-down"})", "unknown view 'upside-down'"},
        {R"({"zoom": {"x": 1, "y": 1, "factor": -2}})", "zoom factor"},
        {R"({"pan": {"from": [1, 2], "to": [1e999, 2]}})", ""},
        {R"({"reset": 1})", "'reset'"},
    };
    for (auto [body, reason] : refused) {
        CAPTURE(std::string(body));
        try {
            applyViewMessage(session, body);
            FAIL("accepted");
        } catch (const RequestError& e) {
            CHECK(std::string(e.what()).find(reason) != std::string::npos);
        }
    }
    CHECK_THROWS_AS(applyClockMessage(session, R"({"time": "later"})"), RequestError);
    CHECK(session.version() == v);
}

} // namespace moire::serve
