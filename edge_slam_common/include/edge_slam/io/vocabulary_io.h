// Vocabulary files. Two formats:
//  - our compact binary format (written by save_vocabulary_binary, loads a 1M-word tree in well
//    under a second): header "ESBOWVOC", version, k, L, node count, FNV-1a checksum, then packed
//    little-endian arrays of parents, 32-byte descriptors, idf weights and leaf flags;
//  - ORB-SLAM2's ORBvoc.txt text format: a line "k L scoring weighting" (only 0 0 = L1 / TF-IDF
//    is supported), then one line per non-root node, line i being node i (the root, node 0,
//    is implicit): "parent_id is_leaf d0 ... d31 weight". Word ids are the leaves in line order,
//    as in ORB-SLAM2.
// Every load error throws std::runtime_error naming the file and what was expected.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "edge_slam/data/bow_vocabulary.h"

namespace edge_slam {

void save_vocabulary_binary(const BowVocabulary& vocabulary, const std::string& path);
void save_vocabulary_text(const BowVocabulary& vocabulary, const std::string& path);  // ORBvoc.txt layout

// Detects the format from the file content.
BowVocabulary load_vocabulary(const std::string& path);
// The same from bytes already in memory; `origin` names them in errors (fuzzing, tests).
BowVocabulary load_vocabulary_from_bytes(const uint8_t* data, size_t size, const std::string& origin);

}  // namespace edge_slam
