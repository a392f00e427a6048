#include "tests/support/Support.h"

#include "runtime/cli/DefineOption.h"
#include "runtime/FrameEval.h"
#include "runtime/output/Render.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace moire::test {

namespace fs = std::filesystem;

std::string sourcePath(const std::string& relative) {
    return std::string(MOIRE_SOURCE_DIR) + "/" + relative;
}

std::string moireBinary() {
    return MOIRE_BINARY;
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE_MESSAGE(in.good(), "cannot read ", path);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string imageBytesWithoutTime(const std::string& path) {
    static const std::regex stamp(R"([0-9]{4}:[0-9]{2}:[0-9]{2} [0-9]{2}:[0-9]{2}:[0-9]{2})");
    return std::regex_replace(readFile(path), stamp, "0000:00:00 00:00:00");
}

namespace {

uint64_t waitForPeakMemory(pid_t pid, int execed, int& status) {
    char byte;
    while (::read(execed, &byte, 1) < 0 && errno == EINTR) {
    }
    ::close(execed);
    uint64_t peak = 0;
    const std::string statusPath = "/proc/" + std::to_string(pid) + "/status";
    for (;;) {
        const pid_t done = ::waitpid(pid, &status, WNOHANG);
        REQUIRE(done >= 0);
        if (done == pid) return peak;
        std::ifstream in(statusPath);
        for (std::string line; std::getline(in, line);)
            if (line.rfind("VmHWM:", 0) == 0)
                peak = std::max<uint64_t>(peak, std::stoull(line.substr(6)) * 1024);
        ::usleep(3000);
    }
}

} // namespace

Measured runMeasured(const std::vector<std::string>& args, const TempDir& dir,
                     uint64_t addressLimit) {
    const std::string errPath = dir.file("measured.err");
    std::vector<std::string> argv = {moireBinary()};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> av;
    for (std::string& a : argv) av.push_back(a.data());
    av.push_back(nullptr);
    int execed[2];
    REQUIRE(::pipe2(execed, O_CLOEXEC) == 0);
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        const int err = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int null = ::open("/dev/null", O_RDWR);
        if (err < 0 || null < 0 || ::chdir(dir.path().c_str()) != 0) ::_exit(126);
        ::dup2(null, 0), ::dup2(null, 1), ::dup2(err, 2);
        if (addressLimit) {
            rlimit rl{addressLimit, addressLimit};
            if (::setrlimit(RLIMIT_AS, &rl) != 0) ::_exit(126);
        }
        ::execv(av[0], av.data());
        ::_exit(127);
    }
    ::close(execed[1]);
    int status = 0;
    Measured m;
    m.maxRss = waitForPeakMemory(pid, execed[0], status);
    m.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    m.err = readFile(errPath);
    fs::remove(errPath);
    return m;
}

std::unique_ptr<SceneProgram> compileOk(const std::string& text, const CompileOptions& options,
                                        const std::string& path) {
    CompileResult r = compileScene(path, text, options);
    INFO("diagnostics:\n", r.diagnostics);
    REQUIRE(r.program != nullptr);
    return std::move(r.program);
}

std::string compileErrors(const std::string& text, const std::string& path) {
    // A case whose first line is `// moire ARGS...` is compiled with that command line's -D
    // values (split at spaces), and its command-line errors are its diagnostics.
    CompileOptions options;
    if (text.starts_with("// moire ")) {
        std::string line = text.substr(3, text.find('\n') - 3);
        std::vector<std::string> words;
        for (size_t at = 0; at < line.size();) {
            size_t end = std::min(line.find(' ', at), line.size());
            words.push_back(line.substr(at, end - at));
            at = end + 1;
        }
        std::vector<const char*> argv;
        for (const std::string& w : words) argv.push_back(w.c_str());
        std::string diagnostics;
        if (!cli::collectDefines(static_cast<int>(argv.size()), argv.data(), options.defines,
                                 diagnostics))
            return diagnostics;
    }
    CompileResult r = compileScene(path, text, options);
    if (r.program) {
        // Frame-time errors (image size, zoom) are diagnostics too.
        FrameValues fv;
        std::string diags;
        bool ok = evaluateFrame(*r.program, FrameRequest{}, fv, diags);
        INFO("scene unexpectedly valid:\n", text);
        REQUIRE_FALSE(ok);
        return diags;
    }
    return r.diagnostics;
}

std::vector<std::string> availableBackends() {
    std::vector<std::string> out;
    for (const std::string& name : backendNames()) {
        try {
            if (makeBackend(name)) out.push_back(name);
        } catch (const std::exception& e) {
            skip("backend '" + name + "': " + e.what());
        }
    }
    return out;
}

std::unique_ptr<Backend> makeBackendOrSkip(const std::string& name) {
    try {
        return makeBackend(name);
    } catch (const std::exception& e) {
        skip("backend '" + name + "': " + e.what());
        return nullptr;
    }
}

namespace {

// The frame's values for `program` at size width x height (0: the scene's), time `t`, with
// `literals` in place of the program's own when given; fails the current test if the frame
// cannot be drawn.
FrameValues frameOf(const SceneProgram& program, int width, int height, double t,
                    const std::vector<double>* literals = nullptr) {
    FrameRequest req;
    req.time = t;
    req.width = width;
    req.height = height;
    req.literals = literals;
    FrameValues fv;
    std::string diags;
    INFO(diags);
    REQUIRE(evaluateFrame(program, req, fv, diags));
    return fv;
}

} // namespace

Image renderScene(const SceneProgram& program, Backend& backend, int width, int height, double t) {
    return renderFrame(program, backend, frameOf(program, width, height, t));
}

int literalSlot(const SceneProgram& program, double value) {
    for (size_t i = 0; i < program.literals.size(); ++i)
        if (program.literals[i] == value) return static_cast<int>(i);
    FAIL("no literal ", value);
    return -1;
}

Image runWithLiterals(const SceneProgram& program, CompiledKernel& kernel,
                      const std::vector<double>& literals, int width, int height, double t) {
    FrameValues fv = frameOf(program, width, height, t, &literals);
    Image img(fv.width, fv.height, kernel.numOutputs());
    KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    kernel.runTile(frame, TileRect{0, 0, fv.width, fv.height}, img.pixels.data(),
                   static_cast<size_t>(fv.width) * kernel.numOutputs());
    return img;
}

Image renderWindow(const SceneProgram& program, Backend& backend, int x0, int y0, int width,
                   int height, double t) {
    FrameRequest req;
    req.time = t;
    FrameValues fv;
    std::string diags;
    INFO(diags);
    REQUIRE(evaluateFrame(program, req, fv, diags));
    auto kernel = backend.compile(program.kernel);
    Image img(width, height, kernel->numOutputs());
    KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    kernel->runTile(frame, TileRect{x0, y0, x0 + width, y0 + height}, img.pixels.data(),
                    static_cast<size_t>(width) * kernel->numOutputs());
    return img;
}

ImageDiff compareImages(const Image& a, const Image& b, double tolerance, int channels) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    ImageDiff d;
    double sum = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < channels; ++c) {
                double diff = std::fabs(static_cast<double>(a.at(x, y, c)) - b.at(x, y, c));
                if (!(diff == diff)) diff = 1e9; // NaN counts as a full miss
                d.maxAbs = std::max(d.maxAbs, diff);
                sum += diff;
                if (diff > tolerance) ++d.over;
                ++d.samples;
            }
    d.meanAbs = d.samples ? sum / d.samples : 0.0;
    return d;
}

std::vector<std::string> exampleScenes() {
    std::vector<std::string> out;
    for (const auto& entry : fs::directory_iterator(sourcePath("examples")))
        if (entry.path().extension() == ".moire")
            out.push_back("examples/" + entry.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

TempDir::TempDir(const std::string& tag) {
    static int counter = 0;
    fs::path p = fs::temp_directory_path() / ("moire-" + tag + "-" + std::to_string(::getpid()) +
                                              "-" + std::to_string(counter++));
    fs::remove_all(p);
    fs::create_directories(p);
    path_ = p.string();
}

TempDir::~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
}

void TempDir::write(const std::string& name, const std::string& text) const {
    std::ofstream out(file(name), std::ios::binary);
    out << text;
    REQUIRE_MESSAGE(out.good(), "cannot write ", file(name));
}

std::vector<std::string> TempDir::names(const std::string& except) const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(path_))
        if (e.path().filename() != except) v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
}

CommandResult runCommand(const std::string& command) {
    char outName[] = "/tmp/moire-test-out-XXXXXX";
    char errName[] = "/tmp/moire-test-err-XXXXXX";
    int outFd = mkstemp(outName);
    int errFd = mkstemp(errName);
    REQUIRE(outFd >= 0);
    REQUIRE(errFd >= 0);
    close(outFd);
    close(errFd);
    std::string full = command + " >" + outName + " 2>" + errName;
    int raw = std::system(full.c_str());
    CommandResult r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = readFile(outName);
    r.err = readFile(errName);
    fs::remove(outName);
    fs::remove(errName);
    return r;
}

CommandResult runMoireInSourceRoot(const std::string& args) {
    return runCommand("cd '" + sourcePath("") + "' && '" + moireBinary() + "' " + args);
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

} // namespace moire::test
