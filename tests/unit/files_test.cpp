#include "base/files.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace dc::base {
namespace {

namespace fs = std::filesystem;

class AtomicWriteTest : public testing::Test {
protected:
    void SetUp() override {
        std::string pattern = testing::TempDir() + "depthcloud-files-XXXXXX";
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        dir_ = pattern;
        path_ = dir_ + "/settings.json";
        ASSERT_TRUE(writeTextFile(path_, kOld));
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string contents() const {
        std::ifstream in(path_, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), {}};
    }
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(dir_))
            names.push_back(e.path().filename().string());
        return names;
    }
    Status writeNew(const AtomicWriteFault& fault) {
        return writeFileAtomically(path_, {reinterpret_cast<const std::uint8_t*>(kNew.data()), kNew.size()},
                                   fault);
    }

    const std::string kOld = "the old, good file";
    const std::string kNew = std::string(100000, 'n'); // larger than one page: a real write
    std::string dir_;
    std::string path_;
};

TEST_F(AtomicWriteTest, TheSeamSeesEveryStepInOrderAndTheNewFileReplacesTheOld) {
    std::vector<AtomicWriteStep> steps;
    ASSERT_TRUE(writeNew([&](AtomicWriteStep step) {
        steps.push_back(step);
        return 0;
    }));
    EXPECT_EQ(steps, (std::vector<AtomicWriteStep>{AtomicWriteStep::Open, AtomicWriteStep::Write,
                                                   AtomicWriteStep::Sync, AtomicWriteStep::Rename,
                                                   AtomicWriteStep::SyncDirectory}));
    EXPECT_EQ(contents(), kNew);
    EXPECT_EQ(entries(), std::vector<std::string>{"settings.json"});
}

TEST_F(AtomicWriteTest, AFailureBeforeTheRenameLeavesTheOldFileAndNoTemporary) {
    for (const AtomicWriteStep failing :
         {AtomicWriteStep::Open, AtomicWriteStep::Write, AtomicWriteStep::Sync, AtomicWriteStep::Rename}) {
        SCOPED_TRACE(static_cast<int>(failing));
        bool temporaryExisted = false;
        const Status s = writeNew([&](AtomicWriteStep step) {
            if (step != failing)
                return 0;
            temporaryExisted = entries().size() == 2; // from Write on, the temporary is there to clean up
            return failing == AtomicWriteStep::Write ? -ENOSPC : -EIO;
        });
        ASSERT_FALSE(s);
        EXPECT_NE(s.error().message.find(failing == AtomicWriteStep::Write ? std::strerror(ENOSPC)
                                                                           : std::strerror(EIO)),
                  std::string::npos)
            << s.error().message;
        EXPECT_EQ(temporaryExisted, failing != AtomicWriteStep::Open);
        EXPECT_EQ(contents(), kOld);
        EXPECT_EQ(entries(), std::vector<std::string>{"settings.json"});
    }
}

TEST_F(AtomicWriteTest, AFailureToFlushTheDirectoryIsReportedWithTheNewFileWhole) {
    const Status s =
        writeNew([](AtomicWriteStep step) { return step == AtomicWriteStep::SyncDirectory ? -EIO : 0; });
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("could not flush its directory"), std::string::npos);
    EXPECT_EQ(contents(), kNew) << "renamed already: the new file, never a part of it";
    EXPECT_EQ(entries(), std::vector<std::string>{"settings.json"});
}

} // namespace
} // namespace dc::base
