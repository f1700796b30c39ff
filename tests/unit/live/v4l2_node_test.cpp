#include "devices/uvc/v4l2/handles.h"
#include "devices/uvc/v4l2/v4l2_node.h"
#include "tests/unit/live/fake_v4l2.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

namespace dc::devices::v4l2 {
namespace {

using testing::FakeFrame;
using testing::FakeV4l2;
using testing::z16Bytes;

constexpr const char* kNode = "/dev/video0";

FakeV4l2& depthCamera(FakeV4l2& fake, int w = 4, int h = 2) {
    fake.addNode(kNode, {.modes = {{V4L2_PIX_FMT_Z16, w, h, {30, 15}}, {V4L2_PIX_FMT_Z16, 8, 6, {30}}}});
    return fake;
}

// Opens the depth camera's node at 4x2 Z16 with four buffers and starts it.
void startStreaming(V4l2Node& node) {
    ASSERT_EQ(node.open(kNode), 0);
    V4l2Format f{V4L2_PIX_FMT_Z16, 4, 2, 0, 0};
    ASSERT_EQ(node.setFormat(f), 0);
    ASSERT_EQ(node.allocateBuffers(), 4);
    ASSERT_EQ(node.streamOn(), 0);
}

FakeFrame frameOf(std::uint16_t base, int count = 8) {
    std::vector<std::uint16_t> px(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i)
        px[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(base + i);
    return {z16Bytes(px)};
}

// libcamera's order: open, formats, buffers, stream on/off, capture, each over the same node.
TEST(V4l2Node, OpensListsModesNegotiatesAndStreams) {
    FakeV4l2 fake;
    depthCamera(fake);
    V4l2Node node(fake);
    ASSERT_EQ(node.open(kNode), 0);
    EXPECT_TRUE(node.capability().canCapture());
    EXPECT_EQ(node.capability().driver, "fakecam");
    const auto modes = node.allModes();
    ASSERT_EQ(modes.size(), 2u);
    EXPECT_EQ(modes[0].framesPerSecond, (std::vector<double>{30, 15}));
    V4l2Format f{V4L2_PIX_FMT_Z16, 4, 2, 0, 0};
    ASSERT_EQ(node.setFormat(f), 0);
    EXPECT_EQ(f.bytesPerLine, 8u);
    ASSERT_EQ(node.allocateBuffers(), 4);
    EXPECT_EQ(fake.mappings(), 4);
    ASSERT_EQ(node.streamOn(), 0);
    EXPECT_EQ(fake.queued(kNode), 4u);
    fake.pushFrame(kNode, frameOf(100));
    const DequeueResult d = node.dequeue();
    ASSERT_EQ(d.kind, DequeueResult::Kind::Buffer) << d.message;
    EXPECT_EQ(d.buffer.bytes.size(), 16u);
    EXPECT_EQ(d.buffer.bytes[0], 100);
    EXPECT_TRUE(d.buffer.monotonicTimestamp);
    EXPECT_EQ(node.dequeue().kind, DequeueResult::Kind::NotReady);
    EXPECT_EQ(node.requeue(d.buffer.index), 0);
    EXPECT_EQ(node.requeue(d.buffer.index), -EINVAL) << "a buffer cannot be queued twice";
    node.close();
    EXPECT_EQ(fake.mappings(), 0);
    EXPECT_EQ(fake.openFds(), 0);
}

TEST(SyscallFunnel, RetriesAnEintrStormAndGivesUpOnAnEndlessOne) {
    FakeV4l2 fake;
    depthCamera(fake);
    V4l2Node node(fake);
    fake.interruptIoctl(VIDIOC_QUERYCAP, 500);
    ASSERT_EQ(node.open(kNode), 0) << "500 EINTRs in a row are retried";
    fake.interruptIoctl(VIDIOC_G_FMT, kMaxInterruptedRetries + 5);
    V4l2Format f;
    EXPECT_EQ(node.getFormat(f), -EINTR) << "an endless storm is reported, not spun on";
    fake.interruptPolls(50);
    pollfd p{node.fd(), POLLIN, 0};
    EXPECT_GE(xpoll(fake, &p, 1, 10), 0);
}

TEST(V4l2Node, BadBuffersAreDroppedRequeuedAndDescribed) {
    FakeV4l2 fake;
    depthCamera(fake);
    V4l2Node node(fake);
    ASSERT_NO_FATAL_FAILURE(startStreaming(node));
    FakeFrame error = frameOf(1);
    error.flags = V4L2_BUF_FLAG_ERROR;
    FakeFrame shortFrame = frameOf(1, 3);
    FakeFrame huge = frameOf(1);
    huge.bytesused = 1u << 20;
    FakeFrame zero = frameOf(1);
    zero.bytesused = 0;
    for (const FakeFrame& bad : {error, shortFrame, huge, zero}) {
        fake.pushFrame(kNode, bad);
        const DequeueResult d = node.dequeue();
        EXPECT_EQ(d.kind, DequeueResult::Kind::Dropped);
        EXPECT_NE(d.message.find(kNode), std::string::npos) << d.message;
        EXPECT_EQ(fake.queued(kNode), 4u) << "the dropped buffer went back to the driver: " << d.message;
    }
    FakeFrame garbageIndex = frameOf(1);
    garbageIndex.index = 77;
    fake.pushFrame(kNode, garbageIndex);
    const DequeueResult g = node.dequeue();
    EXPECT_EQ(g.kind, DequeueResult::Kind::Dropped);
    EXPECT_NE(g.message.find("77"), std::string::npos);
    fake.pushFrame(kNode, frameOf(9));
    EXPECT_EQ(node.dequeue().kind, DequeueResult::Kind::Buffer) << "good frames still come through";
}

TEST(V4l2Node, UnplugFailsWithEnodevAndCloseReleasesEverything) {
    FakeV4l2 fake;
    depthCamera(fake);
    {
        V4l2Node node(fake);
        ASSERT_NO_FATAL_FAILURE(startStreaming(node));
        fake.unplug(kNode);
        const DequeueResult d = node.dequeue();
        EXPECT_EQ(d.kind, DequeueResult::Kind::Failed);
        EXPECT_EQ(d.error, -ENODEV);
    }
    EXPECT_EQ(fake.mappings(), 0);
    EXPECT_EQ(fake.openFds(), 0);
}

TEST(WaitForNodes, AnEventFdSignalledFromAnotherThreadWakesThePoll) {
    FakeV4l2 fake;
    depthCamera(fake);
    V4l2Node node(fake);
    ASSERT_NO_FATAL_FAILURE(startStreaming(node));
    EventFd stop;
    ASSERT_EQ(stop.create(fake), 0);
    std::vector<NodeReadiness> ready;
    V4l2Node* nodes[] = {&node};
    EXPECT_EQ(waitForNodes(fake, nodes, &stop, 0, ready), 0);
    ASSERT_EQ(stop.signal(), 0);
    EXPECT_EQ(waitForNodes(fake, nodes, &stop, 1000, ready), -ECANCELED);
    EXPECT_EQ(waitForNodes(fake, nodes, &stop, 0, ready), 0) << "the signal was consumed";
    fake.pushFrame(kNode, frameOf(1));
    ASSERT_EQ(waitForNodes(fake, nodes, &stop, 0, ready), 1);
    EXPECT_TRUE(ready[0].buffer);
}

} // namespace
} // namespace dc::devices::v4l2
