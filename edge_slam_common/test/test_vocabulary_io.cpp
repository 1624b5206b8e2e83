// Vocabulary files: binary and ORBvoc.txt round trips, a hand-written text vocabulary, and
// rejection of corrupt files with messages naming the file and the problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/feature/descriptor_distance.h"
#include "edge_slam/io/vocabulary_io.h"

using namespace edge_slam;
namespace fs = std::filesystem;

namespace {

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("edge_slam_vocabulary_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// Asserts that loading fails with a std::runtime_error mentioning the file and `expected`.
void expect_load_error(const std::string& path, const std::string& expected) {
  try {
    load_vocabulary(path);
    ADD_FAILURE() << "loading " << path << " should have failed with '" << expected << "'";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << "message: " << message << "\nexpected: " << expected;
  }
}

std::vector<cv::Mat> clustered_images(int images, int features, uint32_t seed) {
  std::mt19937 rng(seed);
  cv::Mat prototypes(200, kDescriptorBytes, CV_8U);
  for (int r = 0; r < prototypes.rows; ++r)
    for (int c = 0; c < kDescriptorBytes; ++c) prototypes.at<uint8_t>(r, c) = static_cast<uint8_t>(rng());
  std::vector<cv::Mat> out;
  for (int i = 0; i < images; ++i) {
    cv::Mat m(features, kDescriptorBytes, CV_8U);
    for (int r = 0; r < features; ++r) {
      prototypes.row(static_cast<int>(rng() % prototypes.rows)).copyTo(m.row(r));
      for (int f = static_cast<int>(rng() % 6); f > 0; --f) {
        const int bit = static_cast<int>(rng() % 256);
        m.at<uint8_t>(r, bit / 8) ^= static_cast<uint8_t>(1u << (bit % 8));
      }
    }
    out.push_back(m);
  }
  return out;
}

BowVocabulary small_trained_vocabulary(const std::vector<cv::Mat>& images) {
  VocabularyParams params;
  params.branching = 5;
  params.levels = 4;
  BowVocabulary v;
  v.train(images, params);
  return v;
}

void expect_same_transforms(const BowVocabulary& a, const BowVocabulary& b, const std::vector<cv::Mat>& images) {
  ASSERT_EQ(a.size(), b.size());
  for (const cv::Mat& image : images) {
    BowVector bow_a, bow_b;
    FeatureVector fv_a, fv_b;
    a.transform(image, bow_a, fv_a, 2);
    b.transform(image, bow_b, fv_b, 2);
    EXPECT_EQ(bow_a, bow_b);
    EXPECT_EQ(fv_a, fv_b);
  }
}

std::string descriptor_text(uint8_t byte) {
  std::string s;
  for (int i = 0; i < kDescriptorBytes; ++i) s += std::to_string(byte) + " ";  // ORBvoc.txt style spacing
  return s;
}

cv::Mat descriptor_rows(const std::vector<uint8_t>& bytes) {
  cv::Mat m(static_cast<int>(bytes.size()), kDescriptorBytes, CV_8U);
  for (size_t i = 0; i < bytes.size(); ++i) m.row(static_cast<int>(i)).setTo(bytes[i]);
  return m;
}

// k=2, L=2. Root -> {1: all 0x00, 2: all 0xFF}; 1 -> words {3: 0x00 (0.5), 4: 0x0F (1.0)};
// 2 -> words {5: 0xFF (2.0), 6: 0xF0 (0, in every image)}.
std::string tiny_text_vocabulary() {
  return "2 2 0 0\n"
         "0 0 " + descriptor_text(0x00) + "0\n"
         "0 0 " + descriptor_text(0xFF) + "0\n"
         "1 1 " + descriptor_text(0x00) + "0.5\n"
         "1 1 " + descriptor_text(0x0F) + "1\n"
         "2 1 " + descriptor_text(0xFF) + "2\n"
         "2 1 " + descriptor_text(0xF0) + "0\n";
}

}  // namespace

TEST(VocabularyIo, BinaryRoundTripGivesIdenticalTransforms) {
  TempDir dir;
  const std::vector<cv::Mat> images = clustered_images(20, 120, 1);
  const BowVocabulary trained = small_trained_vocabulary(images);
  save_vocabulary_binary(trained, dir.file("voc.bin"));
  const BowVocabulary loaded = load_vocabulary(dir.file("voc.bin"));
  EXPECT_EQ(loaded.branching(), 5);
  EXPECT_EQ(loaded.levels(), 4);
  for (WordId w = 0; w < trained.size(); ++w) EXPECT_EQ(trained.idf(w), loaded.idf(w));
  expect_same_transforms(trained, loaded, images);
  expect_same_transforms(trained, loaded, clustered_images(3, 100, 2));
}

TEST(VocabularyIo, TextRoundTripGivesIdenticalTransforms) {
  TempDir dir;
  const std::vector<cv::Mat> images = clustered_images(20, 120, 3);
  const BowVocabulary trained = small_trained_vocabulary(images);
  save_vocabulary_text(trained, dir.file("voc.txt"));
  const BowVocabulary loaded = load_vocabulary(dir.file("voc.txt"));
  for (WordId w = 0; w < trained.size(); ++w) EXPECT_EQ(trained.idf(w), loaded.idf(w));
  expect_same_transforms(trained, loaded, images);
  // The text file starts with the ORBvoc.txt header line.
  EXPECT_EQ(read_bytes(dir.file("voc.txt")).substr(0, 8), "5 4 0 0\n");
}

TEST(VocabularyIo, HandWrittenOrbSlamTextVocabulary) {
  TempDir dir;
  write_bytes(dir.file("ORBvoc.txt"), tiny_text_vocabulary());
  const BowVocabulary v = load_vocabulary(dir.file("ORBvoc.txt"));
  EXPECT_EQ(v.branching(), 2);
  EXPECT_EQ(v.levels(), 2);
  ASSERT_EQ(v.size(), 4u);  // words are the leaves, in file order
  EXPECT_EQ(v.node_count(), 7u);
  EXPECT_EQ(v.idf(0), 0.5);
  EXPECT_EQ(v.idf(1), 1.0);
  EXPECT_EQ(v.idf(2), 2.0);
  EXPECT_EQ(v.idf(3), 0.0);
  EXPECT_EQ(v.node_of_word(0), 3u);
  EXPECT_EQ(v.node_of_word(3), 6u);

  // 0xF8 bytes: 5 bits set -> closer to 0xFF at the root, then to 0xF0 (a zero-weight word).
  const cv::Mat d = descriptor_rows({0x00, 0x0F, 0xFF, 0xF8, 0x0F});
  EXPECT_EQ(v.word_of(d.ptr<uint8_t>(0)), 0u);
  EXPECT_EQ(v.word_of(d.ptr<uint8_t>(1)), 1u);
  EXPECT_EQ(v.word_of(d.ptr<uint8_t>(2)), 2u);
  EXPECT_EQ(v.word_of(d.ptr<uint8_t>(3)), 3u);

  BowVector bow;
  FeatureVector features;
  v.transform(d, bow, features, 1);
  // Weights 0.5 + 2 * 1.0 + 2.0 (the zero-weight word is dropped), L1-normalised over 4.5.
  ASSERT_EQ(bow.size(), 3u);
  EXPECT_DOUBLE_EQ(bow.at(0), 0.5 / 4.5);
  EXPECT_DOUBLE_EQ(bow.at(1), 2.0 / 4.5);
  EXPECT_DOUBLE_EQ(bow.at(2), 2.0 / 4.5);
  // One level up from the leaves: features grouped under nodes 1 and 2.
  const FeatureVector expected{{1u, {0u, 1u, 4u}}, {2u, {2u}}};
  EXPECT_EQ(features, expected);
}

TEST(VocabularyIo, TextWithDbow2HeaderSpacingAndCrlfLineEndsLoads) {
  TempDir dir;
  // DBoW2 writes "k L  scoring weighting" with a double space; files edited on Windows get CRLF.
  std::string text = tiny_text_vocabulary();
  text.replace(0, 8, "2 2  0 0\n");
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  write_bytes(dir.file("plain.txt"), tiny_text_vocabulary());
  write_bytes(dir.file("crlf.txt"), crlf);
  expect_same_transforms(load_vocabulary(dir.file("plain.txt")), load_vocabulary(dir.file("crlf.txt")),
                         {descriptor_rows({0x00, 0x0F, 0xFF, 0xF8, 0x3C})});
}

TEST(VocabularyIo, DepthFirstNodeOrderIsKeptLikeOrbSlam) {
  TempDir dir;
  // DBoW2 creates all children of a node together, then recurses depth-first, so node 3's
  // children (5, 6) come before node 2's (7, 8). k=2, L=3; node 4 is a leaf at depth 2.
  write_bytes(dir.file("dbow2.txt"), "2 3 0 0\n"
                                     "0 0 " + descriptor_text(0x00) + "0\n"      // 1
                                     "0 0 " + descriptor_text(0xFF) + "0\n"      // 2
                                     "1 0 " + descriptor_text(0x00) + "0\n"      // 3
                                     "1 1 " + descriptor_text(0x0F) + "1\n"      // 4: word 0
                                     "3 1 " + descriptor_text(0x00) + "0.5\n"    // 5: word 1
                                     "3 1 " + descriptor_text(0x03) + "0.25\n"   // 6: word 2
                                     "2 1 " + descriptor_text(0xFF) + "2\n"      // 7: word 3
                                     "2 1 " + descriptor_text(0xF0) + "0\n");    // 8: word 4
  const BowVocabulary v = load_vocabulary(dir.file("dbow2.txt"));
  ASSERT_EQ(v.size(), 5u);
  const std::vector<NodeId> word_nodes{4, 5, 6, 7, 8};  // file node ids, words in line order
  for (WordId w = 0; w < 5; ++w) EXPECT_EQ(v.node_of_word(w), word_nodes[w]);

  const cv::Mat d = descriptor_rows({0x00, 0x0F, 0xFF, 0xF8, 0x03});
  const std::vector<WordId> expected_words{1, 0, 3, 4, 2};
  for (int i = 0; i < d.rows; ++i) EXPECT_EQ(v.word_of(d.ptr<uint8_t>(i)), expected_words[i]) << "row " << i;
  BowVector bow;
  FeatureVector features;
  v.transform(d, bow, features, 1);
  const BowVector expected_bow{{0, 1 / 3.75}, {1, 0.5 / 3.75}, {2, 0.25 / 3.75}, {3, 2 / 3.75}};
  ASSERT_EQ(bow.size(), expected_bow.size());
  for (const auto& e : expected_bow) EXPECT_DOUBLE_EQ(bow.at(e.first), e.second);
  // Grouped at depth L - 1 = 2; the shallow leaves 4 and 7 are their own groups.
  const FeatureVector expected_features{{3u, {0u, 4u}}, {4u, {1u}}, {7u, {2u}}};
  EXPECT_EQ(features, expected_features);

  // Saving keeps the numbering.
  save_vocabulary_text(v, dir.file("again.txt"));
  EXPECT_EQ(load_vocabulary(dir.file("again.txt")).to_arrays().parents, v.to_arrays().parents);
  EXPECT_EQ(read_bytes(dir.file("again.txt")).substr(0, 8), "2 3 0 0\n");
}

TEST(VocabularyIo, InterleavedSiblingsAreRenumberedBreadthFirst) {
  TempDir dir;
  // Children of nodes 1 and 3 interleaved: 1, 2 (of 1), 3, 4 (of 1), 5 (of 3), 6 (of 3).
  write_bytes(dir.file("interleaved.txt"), "2 2 0 0\n"
                                           "0 0 " + descriptor_text(0x00) + "0\n"
                                           "1 1 " + descriptor_text(0x00) + "0.5\n"
                                           "0 0 " + descriptor_text(0xFF) + "0\n"
                                           "1 1 " + descriptor_text(0x0F) + "1\n"
                                           "3 1 " + descriptor_text(0xFF) + "2\n"
                                           "3 1 " + descriptor_text(0xF0) + "0\n");
  write_bytes(dir.file("bfs.txt"), tiny_text_vocabulary());
  const BowVocabulary interleaved = load_vocabulary(dir.file("interleaved.txt"));
  const BowVocabulary bfs = load_vocabulary(dir.file("bfs.txt"));
  EXPECT_EQ(interleaved.to_arrays().parents, bfs.to_arrays().parents);
  EXPECT_EQ(interleaved.to_arrays().descriptors, bfs.to_arrays().descriptors);
  expect_same_transforms(interleaved, bfs, {descriptor_rows({0x00, 0x0F, 0xFF, 0xF8, 0x3C})});
}

TEST(VocabularyIo, CorruptBinaryFilesAreRejected) {
  TempDir dir;
  save_vocabulary_binary(small_trained_vocabulary(clustered_images(5, 80, 4)), dir.file("good.bin"));
  const std::string good = read_bytes(dir.file("good.bin"));

  write_bytes(dir.file("truncated.bin"), good.substr(0, good.size() - 17));
  expect_load_error(dir.file("truncated.bin"), "truncated");
  write_bytes(dir.file("header_only.bin"), good.substr(0, 20));
  expect_load_error(dir.file("header_only.bin"), "truncated");
  write_bytes(dir.file("trailing.bin"), good + "x");
  expect_load_error(dir.file("trailing.bin"), "trailing data");

  std::string bad_magic = good;
  bad_magic[0] = 'X';
  write_bytes(dir.file("magic.bin"), bad_magic);
  expect_load_error(dir.file("magic.bin"), "unknown format");

  std::string bad_version = good;
  bad_version[8] = 9;
  write_bytes(dir.file("version.bin"), bad_version);
  expect_load_error(dir.file("version.bin"), "unsupported binary vocabulary version 9");

  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  write_bytes(dir.file("flipped.bin"), flipped);
  expect_load_error(dir.file("flipped.bin"), "checksum mismatch");

  std::string bad_k = good;
  bad_k[12] ^= 1;  // header fields are covered by the checksum too
  write_bytes(dir.file("k.bin"), bad_k);
  expect_load_error(dir.file("k.bin"), "checksum mismatch");
}

TEST(VocabularyIo, CorruptTextFilesAreRejected) {
  TempDir dir;
  const std::string good = tiny_text_vocabulary();
  auto with_line = [&](int line_index, const std::string& replacement) {
    std::istringstream in(good);
    std::string line, out;
    for (int i = 0; std::getline(in, line); ++i) out += (i == line_index ? replacement : line) + "\n";
    return out;
  };

  write_bytes(dir.file("columns.txt"), with_line(3, "1 1 " + descriptor_text(0x00)));  // weight missing
  expect_load_error(dir.file("columns.txt"), "line 4: expected 35 columns");
  write_bytes(dir.file("extra.txt"), with_line(3, "1 1 " + descriptor_text(0x00) + "0.5 7"));
  expect_load_error(dir.file("extra.txt"), "line 4: expected 35 columns");
  write_bytes(dir.file("byte.txt"), with_line(2, "0 0 300 " + descriptor_text(0).substr(2) + "0"));
  expect_load_error(dir.file("byte.txt"), "line 3: column 3 '300' is not a valid descriptor byte");
  write_bytes(dir.file("weight.txt"), with_line(4, "1 1 " + descriptor_text(0x0F) + "abc"));
  expect_load_error(dir.file("weight.txt"), "line 5: column 35 'abc' is not a valid weight");
  write_bytes(dir.file("header.txt"), with_line(0, "2 2 0"));
  expect_load_error(dir.file("header.txt"), "line 1: expected the header");
  write_bytes(dir.file("scoring.txt"), with_line(0, "2 2 3 0"));
  expect_load_error(dir.file("scoring.txt"), "unsupported scoring type 3");
  write_bytes(dir.file("weighting.txt"), with_line(0, "2 2 0 1"));
  expect_load_error(dir.file("weighting.txt"), "unsupported weighting type 1");

  // Structurally wrong trees.
  write_bytes(dir.file("leaf_flag.txt"), with_line(1, "0 1 " + descriptor_text(0) + "0"));
  expect_load_error(dir.file("leaf_flag.txt"), "node 1 is flagged a leaf but has children");
  write_bytes(dir.file("forward_parent.txt"), with_line(1, "5 0 " + descriptor_text(0) + "0"));
  expect_load_error(dir.file("forward_parent.txt"), "node 1 has parent 5, which is not an earlier node");
  write_bytes(dir.file("depth.txt"), "2 1 0 0\n0 0 " + descriptor_text(0) + "0\n1 1 " + descriptor_text(0) + "1\n");
  expect_load_error(dir.file("depth.txt"), "is deeper than L = 1");
  write_bytes(dir.file("branching.txt"), good + "0 1 " + descriptor_text(1) + "1\n");
  expect_load_error(dir.file("branching.txt"), "more than k = 2 children");
  write_bytes(dir.file("negative.txt"), with_line(5, "2 1 " + descriptor_text(0xFF) + "-1"));
  expect_load_error(dir.file("negative.txt"), "weight");
  write_bytes(dir.file("no_words.txt"), "10 6 0 0\n");
  expect_load_error(dir.file("no_words.txt"), "no words");
}

TEST(VocabularyIo, UnreadableOrForeignFilesAreRejected) {
  TempDir dir;
  expect_load_error(dir.file("missing.bin"), "cannot open");
  write_bytes(dir.file("empty.txt"), "");
  expect_load_error(dir.file("empty.txt"), "empty file");
  write_bytes(dir.file("voc.tar.gz"), std::string("\x1f\x8b\x08\x00", 4) + "junk");
  expect_load_error(dir.file("voc.tar.gz"), "gzip-compressed");
  write_bytes(dir.file("image.png"), "\x89PNG\r\n");
  expect_load_error(dir.file("image.png"), "unknown format");
  EXPECT_THROW(save_vocabulary_binary(BowVocabulary(), dir.file("empty.bin")), std::runtime_error);
}

TEST(VocabularyIo, EveryTruncationOrByteFlipFailsCleanlyOrLoadsAValidTree) {
  TempDir dir;
  save_vocabulary_text(small_trained_vocabulary(clustered_images(4, 60, 6)), dir.file("good.txt"));
  save_vocabulary_binary(load_vocabulary(dir.file("good.txt")), dir.file("good.bin"));
  const cv::Mat probe = clustered_images(1, 50, 7)[0];
  for (const std::string name : {"good.txt", "good.bin"}) {
    const std::string good = read_bytes(dir.file(name));
    std::mt19937 rng(8);
    for (size_t cut = 0; cut < good.size(); cut += 1 + rng() % 499) {
      std::string damaged = good.substr(0, cut);
      if (rng() % 2) {  // also flip a byte somewhere before the cut
        if (cut > 0) damaged[rng() % cut] ^= static_cast<char>(1 + rng() % 255);
      }
      write_bytes(dir.file("damaged"), damaged);
      try {
        const BowVocabulary v = load_vocabulary(dir.file("damaged"));
        // Whatever loaded must be a usable tree.
        BowVector bow;
        FeatureVector features;
        v.transform(probe, bow, features, 2);
        for (const auto& e : bow) EXPECT_LT(e.first, v.size());
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(dir.file("damaged")), std::string::npos) << e.what();
      }
    }
  }
}
