// The file picker driven headless: keyboard navigation into a folder, a recording and a Stray capture
// chosen as --source specs, a file that is no source refused with a reason, the Source panel's Browse, and
// the spec a dropped path becomes.

#include "panel_fixture.h"
#include "ui/file_picker.h"
#include "ui/panels.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace dc::ui::test {
namespace {

namespace fs = std::filesystem;

class FilePickerTest : public PanelTest {
protected:
    void SetUp() override {
        PanelTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        root_ = fs::temp_directory_path() / ("dc-picker-" + std::to_string(::getpid()));
        fs::remove_all(root_);
        fs::create_directories(root_ / "captures");
        touch(root_ / "captures" / "take.dcrec");
        touch(root_ / "captures" / "notes.txt");
        fs::create_directories(root_ / "desk_stray" / "depth"); // Stray Scanner's layout
        touch(root_ / "desk_stray" / "rgb.mp4");
        fs::create_directories(root_ / "office_tum");
        touch(root_ / "office_tum" / "rgb.txt");
        touch(root_ / "office_tum" / "depth.txt");
        fs::create_directories(root_ / ".hidden");
        touch(root_ / "lonely.txt");
        state_.directory = root_.string();
        draw_ = [this] {
            if (open_)
                chosen_ = drawFilePicker(state_, &open_);
        };
        frame();
    }

    void TearDown() override { fs::remove_all(root_); }

    static void touch(const fs::path& p) { std::ofstream(p) << "x"; }

    std::vector<std::string> names() const {
        std::vector<std::string> n;
        for (const FilePickerEntry& e : state_.entries)
            n.push_back(e.name);
        return n;
    }

    // Moves the selection to `name` with the arrow keys (from wherever it is).
    void selectWithKeys(const std::string& name) {
        const auto all = names();
        const auto target = static_cast<std::size_t>(std::find(all.begin(), all.end(), name) - all.begin());
        ASSERT_LT(target, all.size()) << name << " is not listed";
        for (std::size_t i = 0; i < all.size() && state_.selected != target; ++i)
            pressKey(state_.selected < target ? ImGuiKey_DownArrow : ImGuiKey_UpArrow);
        ASSERT_EQ(state_.selected, target);
    }

    fs::path root_;
    FilePickerState state_;
    bool open_ = true;
    std::optional<std::string> chosen_;
};

TEST_F(FilePickerTest, ListsFoldersFirstAndOnlySourcesByDefault) {
    EXPECT_EQ(names(), (std::vector<std::string>{"captures", "desk_stray", "office_tum"}));
    EXPECT_EQ(state_.entries[1].kind, PathKind::StrayDirectory);
    EXPECT_EQ(state_.entries[2].kind, PathKind::TumDirectory);
    state_.sourcesOnly = false;
    frame();
    EXPECT_EQ(names(), (std::vector<std::string>{"captures", "desk_stray", "office_tum", "lonely.txt"}));
}

// A recording named by another system (upper case) is listed, and opened, as the recording it is.
TEST_F(FilePickerTest, ARecordingInUpperCaseIsListedAsARecording) {
    touch(root_ / "captures" / "TAKE2.DCREC");
    touch(root_ / "captures" / "X.BAG");
    state_.directory = (root_ / "captures").string();
    frame();
    EXPECT_EQ(names(), (std::vector<std::string>{"TAKE2.DCREC", "X.BAG", "take.dcrec"}));
    EXPECT_EQ(classifyPath(root_ / "captures" / "X.BAG"), PathKind::Recording);
    EXPECT_EQ(sourceSpecForPath((root_ / "captures" / "TAKE2.DCREC").string()).value(),
              "replay:" + (root_ / "captures" / "TAKE2.DCREC").string());
}

TEST_F(FilePickerTest, TheKeyboardEntersAFolderPicksARecordingAndBackspaceGoesUp) {
    selectWithKeys("office_tum");
    selectWithKeys("captures");
    pressKey(ImGuiKey_Enter);
    EXPECT_EQ(fs::path(state_.directory), root_ / "captures");
    EXPECT_EQ(names(), (std::vector<std::string>{"take.dcrec"})) << "notes.txt is no recording";
    pressKey(ImGuiKey_Backspace);
    EXPECT_EQ(fs::path(state_.directory), root_);
    EXPECT_FALSE(chosen_);
    pressKey(ImGuiKey_Enter);
    pressKey(ImGuiKey_Enter);
    ASSERT_TRUE(chosen_);
    EXPECT_EQ(*chosen_, "replay:" + (root_ / "captures" / "take.dcrec").string());
    EXPECT_FALSE(open_) << "the picker closes once a source is chosen";
    ASSERT_FALSE(state_.recentFolders.empty());
    EXPECT_EQ(fs::path(state_.recentFolders.front()), root_ / "captures");
}

TEST_F(FilePickerTest, AStrayFolderOpensAsASourceInsteadOfBeingEntered) {
    selectWithKeys("desk_stray");
    pressKey(ImGuiKey_Enter);
    ASSERT_TRUE(chosen_);
    EXPECT_EQ(*chosen_, "replay:" + (root_ / "desk_stray").string());
    EXPECT_EQ(fs::path(state_.directory), root_);
}

TEST_F(FilePickerTest, AFileThatIsNoSourceIsRefusedWithAReason) {
    state_.sourcesOnly = false;
    frame();
    selectWithKeys("lonely.txt");
    pressKey(ImGuiKey_Enter);
    EXPECT_FALSE(chosen_);
    EXPECT_TRUE(open_);
    EXPECT_NE(state_.message.find("lonely.txt: not a recording"), std::string::npos) << state_.message;
}

TEST_F(FilePickerTest, BrowseInTheSourcePanelOpensThePickerAtARecentFolder) {
    SourcePanelState panel;
    bool sourceOpen = true;
    const SourceList list{
        "synthetic", {}, {{"take", "replay:" + (root_ / "captures" / "take.dcrec").string()}}, {}};
    std::optional<std::string> opened;
    draw_ = [&] {
        if (auto spec = drawSourcePanel(list, panel, &sourceOpen))
            opened = spec;
    };
    frame();
    const auto browse = locate(kSourceTitle, "Browse...");
    ASSERT_TRUE(browse);
    click(*browse);
    ASSERT_TRUE(panel.filesOpen);
    ASSERT_EQ(panel.files.recentFolders, (std::vector<std::string>{(root_ / "captures").string()}));
    EXPECT_EQ(fs::path(panel.files.directory), root_ / "captures") << "it starts in the newest recent folder";
    pressKey(ImGuiKey_Enter);
    ASSERT_TRUE(opened);
    EXPECT_EQ(*opened, "replay:" + (root_ / "captures" / "take.dcrec").string());
    EXPECT_FALSE(panel.filesOpen);
}

TEST_F(FilePickerTest, ADroppedPathBecomesASourceSpecOrSaysWhyNot) {
    EXPECT_EQ(*sourceSpecForPath((root_ / "desk_stray").string()),
              "replay:" + (root_ / "desk_stray").string());
    EXPECT_EQ(*sourceSpecForPath((root_ / "office_tum").string()),
              "replay:" + (root_ / "office_tum").string());
    const std::string take = (root_ / "captures" / "take.dcrec").string();
    EXPECT_EQ(*sourceSpecForPath(take), "replay:" + take);
    const auto folder = sourceSpecForPath((root_ / "captures").string());
    ASSERT_FALSE(folder);
    EXPECT_NE(folder.error().message.find("a folder, but neither a Stray Scanner capture"),
              std::string::npos);
    const auto missing = sourceSpecForPath((root_ / "gone.dcrec").string());
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("does not exist"), std::string::npos);
    EXPECT_FALSE(sourceSpecForPath((root_ / "lonely.txt").string()));
}

} // namespace
} // namespace dc::ui::test
