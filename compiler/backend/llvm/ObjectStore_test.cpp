// The JIT's object store: a second backend with the same store loads every module's code
// instead of compiling it, and draws the same pixels; an object that is not one is compiled
// again and replaced; code built with other options is kept apart.
#include "compiler/backend/llvm/LlvmJit.h"
#include "tests/support/Support.h"

#include <cstring>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <map>
#include <mutex>

using namespace moire;

namespace {

struct MemoryStore : ObjectStore {
    std::mutex mutex;
    std::map<std::string, std::string> objects;
    int stores = 0;
    std::optional<std::string> load(const std::string& key) override {
        std::lock_guard<std::mutex> lock(mutex);
        auto it = objects.find(key);
        if (it == objects.end()) return std::nullopt;
        return it->second;
    }
    void store(const std::string& key, std::string_view object) override {
        std::lock_guard<std::mutex> lock(mutex);
        objects[key] = std::string(object);
        ++stores;
    }
};

std::unique_ptr<SceneProgram> program(int layers) {
    std::string text = "scene { size = (90, 60) }\n";
    for (int i = 0; i < layers; ++i)
        text += fmt::format("layer {{ family = circles; spacing = 5; origin = ({}, 1) }}\n", i);
    text += "layer { family = squares; spacing = 9; turn = 3deg }\n";
    return test::compileOk(text);
}

std::vector<float> pixels(LlvmJitBackend& jit, const SceneProgram& p) {
    Image img = test::renderScene(p, jit);
    return {img.pixels.begin(), img.pixels.end()};
}

bool same(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

} // namespace

TEST_CASE("jit object store: a second backend loads the code instead of compiling it") {
    for (int layers : {1, 30}) { // one module, and a chunked kernel of several
        CAPTURE(layers);
        auto p = program(layers);
        auto store = std::make_shared<MemoryStore>();
        LlvmJitBackend::Options o;
        o.objects = store;
        LlvmJitBackend first(o);
        std::vector<float> ref = pixels(first, *p);
        CHECK(first.storeHits() == 0);
        int modules = store->stores;
        CHECK(modules >= 1);
        if (layers > 1) CHECK(modules > 1);

        LlvmJitBackend second(o);
        CHECK(same(ref, pixels(second, *p)));
        CHECK(second.storeHits() == modules);
        CHECK(store->stores == modules); // nothing compiled, nothing stored again

        // Without a store, the same pixels.
        LlvmJitBackend plain;
        CHECK(same(ref, pixels(plain, *p)));

        // Objects that are not objects are compiled again, and replaced.
        for (auto& [key, bytes] : store->objects) bytes = "not an object file";
        LlvmJitBackend third(o);
        CHECK(same(ref, pixels(third, *p)));
        CHECK(third.storeHits() == 0);
        CHECK(store->stores == 2 * modules);
        for (auto& [key, bytes] : store->objects) CHECK(bytes != "not an object file");
    }
}

TEST_CASE("jit object store: code built with other options is kept under other keys") {
    auto p = program(30);
    auto store = std::make_shared<MemoryStore>();
    LlvmJitBackend::Options widest, four;
    widest.objects = four.objects = store;
    four.chunkVectorWidth = 4;
    LlvmJitBackend a(widest);
    std::vector<float> ref = pixels(a, *p);
    size_t keys = store->objects.size();
    LlvmJitBackend b(four);
    CHECK(same(ref, pixels(b, *p)));
    CHECK(b.storeHits() == 0);
    CHECK(store->objects.size() == 2 * keys);
}
