// core/ against hostile input: reading special and huge files, writing several outputs as one,
// echoing input in messages, and the keyed hash of the program cache.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/hash.h"
#include "core/quote.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

namespace fs = std::filesystem;

std::string read_error(const fs::path& path, std::size_t max_bytes = kMaxInputBytes) {
    try {
        read_file(path, max_bytes);
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

TEST(CoreFiles, ReadRefusesWhatIsNotARegularFileWithoutBlocking) {
    const fs::path dir = test::temp_dir("core_files_read");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);  // no writer: opening it must not block
    EXPECT_NE(read_error(dir / "fifo").find("a FIFO, not a regular file"), std::string::npos) << read_error(dir / "fifo");
    EXPECT_NE(read_error(dir).find("a directory, not a regular file"), std::string::npos);
    EXPECT_NE(read_error("/dev/zero").find("a character device"), std::string::npos);
    EXPECT_NE(read_error(dir / "missing").find("cannot read"), std::string::npos);
}

TEST(CoreFiles, ReadRefusesFilesOverTheLimitBeforeReadingThem) {
    const fs::path dir = test::temp_dir("core_files_cap");
    test::write_text(dir / "small", "0123456789");
    EXPECT_EQ(read_file(dir / "small", 10), "0123456789");
    EXPECT_NE(read_error(dir / "small", 9).find("10 bytes; at most 9 are read"), std::string::npos) << read_error(dir / "small", 9);
    test::write_text(dir / "huge", "");
    fs::resize_file(dir / "huge", kMaxInputBytes + 1);  // sparse: no disk space used
    EXPECT_NE(read_error(dir / "huge").find("at most"), std::string::npos);
}

TEST(CoreFiles, WriteAllWritesEveryOutputOrNone) {
    const fs::path dir = test::temp_dir("core_files_all");
    const Output failing{dir / "b.txt", [](std::ostream&) { throw InputError("b.txt: cannot write: refused"); }};
    EXPECT_THROW(write_all({text_output(dir / "a.txt", "a"), failing}), InputError);
    EXPECT_TRUE(fs::is_empty(dir)) << "a failed write left a file behind";
    write_all({text_output(dir / "a.txt", "a"), text_output(dir / "b.txt", "b")});
    EXPECT_EQ(read_file(dir / "a.txt"), "a");
    EXPECT_EQ(read_file(dir / "b.txt"), "b");
}

TEST(CoreFiles, SpecialFilesAreWrittenInPlaceAndTheirErrorsReported) {
    write_file_atomic("/dev/null", "fine");
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    try {
        write_file_atomic("/dev/full", "x");
        FAIL() << "writing /dev/full succeeded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/dev/full: write failed"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
    const fs::path dir = test::temp_dir("core_files_dir_out");
    EXPECT_THROW(write_file_atomic(dir, "x"), InputError);
    EXPECT_THROW(check_output_path(dir), InputError);
    EXPECT_THROW(check_output_path(dir / "missing" / "x.json"), InputError);
    EXPECT_NO_THROW(check_output_path(dir / "x.json"));
}

// Temporary files are created exclusively under names no one can predict: a link planted at the
// names earlier versions used (.STEM.tmp-PID.EXT) is never followed, and an output path that is a
// link is replaced by the file, its target left alone.
TEST(CoreFiles, WritesNeverFollowAPlantedLink) {
    const fs::path dir = test::temp_dir("core_files_links");
    test::write_text(dir / "victim", "precious");
    fs::create_symlink(dir / "victim", dir / fmt::format(".out.tmp-{}.txt", static_cast<long>(::getpid())));
    fs::create_symlink(dir / "victim", dir / "link.txt");
    write_all({text_output(dir / "out.txt", "new"), text_output(dir / "link.txt", "mine")});
    EXPECT_EQ(read_file(dir / "victim"), "precious");
    EXPECT_EQ(read_file(dir / "out.txt"), "new");
    EXPECT_FALSE(fs::is_symlink(dir / "link.txt"));
    EXPECT_EQ(read_file(dir / "link.txt"), "mine");
    std::size_t files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
    EXPECT_EQ(files, 4u) << "a temporary file was left behind";
}

// A FIFO without a reader is refused at once, never waited on; a journal (the sweep cache) is never
// written through a link planted at its path, nor into anything but a regular file.
TEST(CoreFiles, FifoWithoutReaderAndLinkedJournalAreRefused) {
    const fs::path dir = test::temp_dir("core_files_fifo_journal");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    try {
        write_all({text_output(dir / "fifo", "x")});
        FAIL() << "writing to a FIFO without a reader succeeded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("a FIFO with no reader"), std::string::npos) << e.what();
    }
    test::write_text(dir / "victim", "precious");
    fs::create_symlink(dir / "victim", dir / "cache.jsonl");
    try {
        open_journal(dir / "cache.jsonl");
        FAIL() << "a journal was opened through a link";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("a symbolic link"), std::string::npos) << e.what();
    }
    EXPECT_THROW(open_journal(dir / "fifo"), InputError);
    EXPECT_THROW(open_journal(dir), InputError);
    EXPECT_EQ(read_file(dir / "victim"), "precious");
    const int fd = open_journal(dir / "new.jsonl");
    EXPECT_GE(fd, 0);
    ::close(fd);
    EXPECT_TRUE(fs::is_regular_file(dir / "new.jsonl"));
}

// lies_within resolves links and `..` before comparing.
TEST(CoreFiles, LiesWithinResolvesLinksAndDots) {
    const fs::path dir = test::temp_dir("core_files_within");
    fs::create_directories(dir / "a" / "b");
    fs::create_directories(dir / "c");
    fs::create_symlink(dir / "c", dir / "a" / "out");
    EXPECT_TRUE(lies_within(dir / "a" / "b" / "x", dir / "a"));
    EXPECT_TRUE(lies_within(dir / "a", dir / "a"));
    EXPECT_FALSE(lies_within(dir / "a" / ".." / "c" / "x", dir / "a"));
    EXPECT_FALSE(lies_within(dir / "a" / "out" / "x", dir / "a"));
    EXPECT_FALSE(lies_within(dir / "ab", dir / "a"));
    EXPECT_TRUE(lies_within(dir / "a" / "b", dir / "a" / ""));
}

TEST(CoreQuote, EchoedInputIsOneBoundedPrintableLine) {
    EXPECT_EQ(quoted_input("sph\nere\x1b[31m"), "\"sph\\nere\\x1b[31m\"");
    EXPECT_EQ(quoted_input(std::string("a\0b", 3)), "\"a\\x00b\"");
    EXPECT_EQ(quoted_input("say \"hi\"\\"), "\"say \\\"hi\\\"\\\\\"");
    EXPECT_EQ(escaped("caf\xc3\xa9"), "caf\\xc3\\xa9");
    EXPECT_EQ(escaped(std::string(1000, 'x'), 8), "xxxxxxxx...");
    std::string deep;
    for (int i = 0; i < 100000; ++i) deep += "/0";
    const std::string shown = shortened_path(deep);
    EXPECT_LE(shown.size(), 200u);
    EXPECT_EQ(shown.substr(0, 4), "/0/0");
    EXPECT_NE(shown.find("/..."), std::string::npos);
    EXPECT_EQ(shortened_path("/geometries/0/edits/3/radius"), "/geometries/0/edits/3/radius");
}

// The reference vectors of the SipHash paper: key 00..0f, messages 00..(n-1).
TEST(CoreHash, SipHashMatchesTheReferenceVectors) {
    const auto sip = [](std::size_t n) {
        std::string message;
        for (std::size_t i = 0; i < n; ++i) message += static_cast<char>(i);
        return SipHash24(0x0706050403020100ull, 0x0f0e0d0c0b0a0908ull).add(message).value();
    };
    EXPECT_EQ(sip(0), 0x726fdb47dd0e0e31ull);
    EXPECT_EQ(sip(15), 0xa129ca6149be45e5ull);
    EXPECT_EQ(sip(8), 0x93f5f5799a932462ull);
    // Incremental feeding gives the same value as one piece.
    EXPECT_EQ(SipHash24(1, 2).add("ab").add("cdefghij").value(), SipHash24(1, 2).add("abcdefghij").value());
    EXPECT_NE(SipHash24(1, 2).add_part("ab").add_part("c").value(), SipHash24(1, 2).add_part("a").add_part("bc").value());
}

}  // namespace
}  // namespace sdfbrick
