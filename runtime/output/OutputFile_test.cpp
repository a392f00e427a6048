#include "runtime/output/OutputFile.h"
#include "tests/support/Support.h"

#include <csignal>
#include <cstring>
#include <doctest/doctest.h>
#include <filesystem>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using namespace moire;

TEST_CASE("writeFileAtomically writes the bytes exactly and leaves no temporary") {
    test::TempDir dir("outputfile");
    std::vector<unsigned char> bytes(100000);
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 131 % 251);
    writeFileAtomically(dir.file("a.bin"), bytes.data(), bytes.size());
    const std::string back = test::readFile(dir.file("a.bin"));
    CHECK(back == std::string(bytes.begin(), bytes.end()));
    writeFileAtomically(dir.file("a.bin"), "short", 5); // replaces, whole
    CHECK(test::readFile(dir.file("a.bin")) == "short");
    CHECK(dir.names() == std::vector<std::string>{"a.bin"});
}

TEST_CASE("writeFileAtomically: a write cut short by a size limit fails, naming the file") {
    // In a child process: the limit and SIGXFSZ are the process's. 10,000 bytes under a
    // 4,000-byte limit: the first write(2) is short, the next fails with EFBIG.
    test::TempDir dir("outputfile");
    const std::string path = dir.file("big.bin");
    pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::signal(SIGXFSZ, SIG_IGN);
        struct rlimit limit {
            4000, 4000
        };
        if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(3);
        std::vector<char> bytes(10000, 'x');
        try {
            writeFileAtomically(path, bytes.data(), bytes.size());
        } catch (const IoError& e) {
            ::_exit(std::string(e.what()) == "cannot write '" + path + "': " + std::strerror(EFBIG)
                        ? 0
                        : 2);
        }
        ::_exit(1);
    }
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0); // 1: no error; 2: another message; 3: no limit
    CHECK(dir.names().empty());
}

TEST_CASE("writeFileAtomically names the user's path when the directory is wrong") {
    test::TempDir dir("outputfile");
    dir.write("plain", "");
    const std::string path = dir.file("plain/x.png");
    try {
        writeFileAtomically(path, "x", 1);
        FAIL("no error");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()) == "cannot write '" + path + "': Not a directory");
    }
    CHECK_THROWS_WITH(prepareOutputDirectory(path),
                      doctest::Contains(("cannot write into '" + dir.file("plain") + "'").c_str()));
    prepareOutputDirectory(dir.file("new/deeper/x.png"));
    CHECK(fs::is_directory(dir.file("new/deeper")));
}

TEST_CASE("a temporary of this process is its own, and is kept until it is gone") {
    test::TempDir dir("outputfile");
    const std::string temp = temporaryBeside(dir.file("frame.png"));
    CHECK(fs::path(temp).parent_path() == fs::path(dir.path()));
    CHECK(fs::path(temp).extension() == ".png"); // ffmpeg chooses its container by it
    CHECK(temporaryBeside(dir.file("frame.png")) != temp);
    dir.write(fs::path(temp).filename().string(), "partial");
    CHECK(removeStaleTemporaries(dir.file("frame.png")) == 0); // this process is alive

    // The same name from a process that has exited.
    pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        const std::string t = temporaryBeside(dir.file("frame.png"));
        ::_exit(::link(temp.c_str(), t.c_str()) == 0 ? 0 : 1);
    }
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    REQUIRE(WEXITSTATUS(status) == 0);
    CHECK(dir.names().size() == 2);
    CHECK(removeStaleTemporaries(dir.file("frame.png")) == 1);
    CHECK(dir.names() == std::vector<std::string>{fs::path(temp).filename().string()});
}

TEST_CASE("writeFileAtomically: a file replaced keeps its permissions") {
    test::TempDir dir("outputfile-mode");
    dir.write("s.moire", "old text, longer than the new\n");
    REQUIRE(::chmod(dir.file("s.moire").c_str(), 0640) == 0);
    writeFileAtomically(dir.file("s.moire"), "new\n", 4);
    CHECK(test::readFile(dir.file("s.moire")) == "new\n");
    struct stat st {};
    REQUIRE(::stat(dir.file("s.moire").c_str(), &st) == 0);
    CHECK((st.st_mode & 07777) == 0640);
    CHECK(dir.names() == std::vector<std::string>{"s.moire"});
}
