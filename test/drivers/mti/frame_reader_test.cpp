#include "drivers/mti/frame_reader.hpp"

#include <gtest/gtest.h>

#include <numeric>

#include "test/drivers/mti/mti_test_util.hpp"

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;
using test_util::append;
using test_util::read_frames;

Bytes payload_of(std::size_t n, std::uint8_t first) {
  Bytes p(n);
  std::iota(p.begin(), p.end(), first);
  for (auto& b : p)
    if (b == kPreamble) b = 0x00;  // keep stray preambles out where a test counts bytes
  return p;
}

TEST(FrameReader, ReadsAFrameWholeOrByteByByte) {
  const Bytes frame = encode_xbus_frame(0x36, payload_of(49, 1));
  for (const std::size_t chunk : {std::size_t{0}, std::size_t{1}, std::size_t{3}}) {
    FrameReader reader;
    const auto frames = read_frames(reader, frame, chunk);
    ASSERT_EQ(frames.size(), 1u) << "chunk " << chunk;
    EXPECT_EQ(frames[0].mid, 0x36);
    EXPECT_EQ(frames[0].bus_id, kBusIdMaster);
    EXPECT_EQ(frames[0].payload, payload_of(49, 1));
    EXPECT_EQ(frames[0].frame_bytes, frame.size());
    EXPECT_EQ(reader.stats().bytes_discarded, 0u);
    EXPECT_EQ(reader.stats().bytes, frame.size());
  }
}

TEST(FrameReader, GarbageBeforeTheFirstFrameIsDiscardedAndCounted) {
  Bytes stream{0x12, 0x34, 0x56, 0x00, 0x36};
  append(stream, encode_xbus_frame(0x36, payload_of(20, 3)));
  FrameReader reader;
  const auto frames = read_frames(reader, stream);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(reader.stats().bytes_discarded, 5u);
  EXPECT_EQ(reader.stats().bad_frames(), 0u);
}

TEST(FrameReader, BadChecksumIsSkippedCountedAndTheNextFrameStillRead) {
  Bytes corrupt = encode_xbus_frame(0x36, payload_of(30, 5));
  corrupt[10] ^= 0x01;
  Bytes stream = corrupt;
  append(stream, encode_xbus_frame(0x11, {}));
  FrameReader reader;
  const auto frames = read_frames(reader, stream);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].mid, 0x11);
  EXPECT_EQ(reader.stats().bad_checksum, 1u);
  EXPECT_EQ(reader.stats().bytes_discarded, corrupt.size());
}

TEST(FrameReader, ImpossibleExtendedLengthsAreRejected) {
  for (const std::uint16_t length : {std::uint16_t{254}, std::uint16_t{0}, std::uint16_t{2049}, std::uint16_t{0xFFFF}}) {
    Bytes stream{kPreamble, kBusIdMaster, 0x36, kExtendedLength, static_cast<std::uint8_t>(length >> 8),
                 static_cast<std::uint8_t>(length)};
    append(stream, encode_xbus_frame(0x31, {}));
    FrameReader reader;
    const auto frames = read_frames(reader, stream);
    ASSERT_EQ(frames.size(), 1u) << length;
    EXPECT_EQ(frames[0].mid, 0x31);
    EXPECT_EQ(reader.stats().bad_length, 1u) << length;
  }
}

TEST(FrameReader, UnknownBusIdIsRejectedAndBusOneAccepted) {
  Bytes stream{kPreamble, 0x02, 0x31, 0x00, 0xCD};  // a valid sum, but no such bus
  append(stream, encode_xbus_frame(0x31, {}, kBusIdFirstDevice));
  FrameReader reader;
  const auto frames = read_frames(reader, stream);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].bus_id, kBusIdFirstDevice);
  EXPECT_EQ(reader.stats().bad_bus_id, 1u);
}

TEST(FrameReader, ExtendedFramesUpTo2048BytesInArbitraryChunks) {
  const Bytes big = payload_of(2048, 9);
  const Bytes mid_size = payload_of(255, 2);
  Bytes stream = encode_xbus_frame(0x36, big);
  append(stream, encode_xbus_frame(0x36, mid_size));
  for (const std::size_t chunk : {std::size_t{1}, std::size_t{7}, std::size_t{1000}, std::size_t{4096}}) {
    FrameReader reader;
    const auto frames = read_frames(reader, stream, chunk);
    ASSERT_EQ(frames.size(), 2u) << chunk;
    EXPECT_EQ(frames[0].payload, big);
    EXPECT_EQ(frames[1].payload, mid_size);
    EXPECT_EQ(reader.stats().bytes_discarded, 0u);
  }
}

// A bogus header promising a long frame hides real frames until its checksum
// fails; the reader must then find them inside the rejected bytes.
TEST(FrameReader, FramesInsideARejectedCandidateAreFound) {
  Bytes stream{kPreamble, kBusIdMaster, 0x36, kExtendedLength, 0x03, 0x00};  // claims 768 bytes
  for (int i = 0; i < 20; ++i) append(stream, encode_xbus_frame(0x36, payload_of(40, static_cast<std::uint8_t>(i))));
  append(stream, Bytes(300, 0x00));
  for (const std::size_t chunk : {std::size_t{0}, std::size_t{5}, std::size_t{64}}) {
    FrameReader reader;
    const auto frames = read_frames(reader, stream, chunk);
    EXPECT_EQ(frames.size(), 20u) << chunk;
    EXPECT_EQ(reader.stats().bad_checksum, 1u);
    EXPECT_EQ(reader.stats().bytes_discarded, 6u + 300u);
  }
}

TEST(FrameReader, AtTheEndOfAFileFramesBehindAnIncompleteHeaderAreStillRead) {
  Bytes stream{kPreamble, kBusIdMaster, 0x36, kExtendedLength, 0x07, 0xD0};  // claims 2000 bytes
  append(stream, encode_xbus_frame(0x11, {}));
  Bytes cut = encode_xbus_frame(0x36, payload_of(40, 1));
  cut.resize(20);
  append(stream, cut);
  FrameReader reader;
  EXPECT_TRUE(read_frames(reader, stream).empty());  // still waiting for the long frame
  reader.finish();
  const auto last = reader.next();
  ASSERT_TRUE(last);
  EXPECT_EQ(last->mid, 0x11);
  EXPECT_FALSE(reader.next());
  EXPECT_EQ(reader.stats().cut_off, 2u);
  EXPECT_EQ(reader.buffered_bytes(), 0u);
  EXPECT_EQ(reader.stats().bytes_discarded, 6u + 20u);
}

TEST(FrameReader, BytesAfterEachFrameInTheSameReadAreReported) {
  const Bytes a = encode_xbus_frame(0x36, payload_of(49, 1));
  const Bytes b = encode_xbus_frame(0x36, payload_of(30, 2));
  Bytes read = a;
  append(read, b);
  read.push_back(kPreamble);  // the start of a third frame
  const auto frames = read_frames(read);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].bytes_after_in_read, b.size() + 1);
  EXPECT_EQ(frames[1].bytes_after_in_read, 1u);
}

// Garbage, corruption and valid frames, split at every chunk size: the same
// frames and the same counts come out, and every byte is accounted for.
TEST(FrameReader, ChunkingNeverChangesTheResult) {
  Bytes stream{0x01, kPreamble, 0x02};
  for (int i = 0; i < 30; ++i) {
    Bytes f = encode_xbus_frame(static_cast<std::uint8_t>(0x30 + i % 3), payload_of(static_cast<std::size_t>(i * 9), 1));
    if (i % 7 == 3) f.back() ^= 0x55;
    if (i % 11 == 5) f.insert(f.begin(), {0x00, kPreamble, 0x7E});
    append(stream, f);
  }
  FrameReader whole;
  const auto expected = read_frames(whole, stream);
  ASSERT_EQ(expected.size(), 26u);
  for (std::size_t chunk = 1; chunk <= 97; chunk += 4) {
    FrameReader reader;
    const auto frames = read_frames(reader, stream, chunk);
    ASSERT_EQ(frames.size(), expected.size()) << chunk;
    for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(frames[i].payload, expected[i].payload);
    EXPECT_EQ(reader.stats().bad_checksum, whole.stats().bad_checksum);
    EXPECT_EQ(reader.stats().bytes_discarded, whole.stats().bytes_discarded);
    std::size_t framed = 0;
    for (const auto& f : frames) framed += f.frame_bytes;
    EXPECT_EQ(reader.stats().bytes, framed + reader.stats().bytes_discarded + reader.buffered_bytes());
  }
}

TEST(FrameReader, ResetDropsAPartialFrame) {
  Bytes partial = encode_xbus_frame(0x36, payload_of(40, 1));
  partial.resize(10);
  FrameReader reader;
  EXPECT_TRUE(read_frames(reader, partial).empty());
  EXPECT_EQ(reader.buffered_bytes(), 10u);
  reader.reset();
  EXPECT_EQ(reader.buffered_bytes(), 0u);
  const auto frames = read_frames(reader, encode_xbus_frame(0x11, {}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(reader.stats().bytes_discarded, 10u);
}

}  // namespace
}  // namespace tumble::mti
