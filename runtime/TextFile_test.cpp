// Reading scenes and writing them back: only regular files are read, never more than the
// limit, and a write replaces the file whole, keeping its permissions and leaving nothing
// beside it.
#include "runtime/TextFile.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <sys/stat.h>

using namespace moire;

TEST_CASE("text file: a scene is read whole, up to the limit, from a regular file only") {
    test::TempDir dir("textfile");
    std::string text, why;
    dir.write("a.moire", "layer a { family = circles }\n");
    REQUIRE(readWholeFile(dir.file("a.moire"), text, why));
    CHECK(text == "layer a { family = circles }\n");
    dir.write("empty.moire", "");
    REQUIRE(readWholeFile(dir.file("empty.moire"), text, why));
    CHECK(text.empty());

    dir.write("cap.moire", std::string(kMaxSourceBytes, 'x'));
    REQUIRE(readWholeFile(dir.file("cap.moire"), text, why));
    CHECK(text.size() == kMaxSourceBytes);
    dir.write("over.moire", std::string(kMaxSourceBytes + 1, 'x'));
    text = "unchanged";
    CHECK(!readWholeFile(dir.file("over.moire"), text, why));
    CHECK(why == "it is longer than 4 MiB, the most a scene may be");
    CHECK(text == "unchanged");

    CHECK(!readWholeFile(dir.path(), text, why));
    CHECK(why == "it is a directory");
    CHECK(!readWholeFile("/dev/null", text, why));
    CHECK(why == "it is a device, not a file");
    REQUIRE(::mkfifo(dir.file("fifo").c_str(), 0600) == 0);
    CHECK(!readWholeFile(dir.file("fifo"), text, why)); // at once: no writer is waited for
    CHECK(why == "it is a FIFO, not a file");
    CHECK(!readWholeFile(dir.file("missing"), text, why));
    CHECK(why == "No such file or directory");
}
