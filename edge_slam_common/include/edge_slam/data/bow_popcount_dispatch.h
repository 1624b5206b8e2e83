// The default x86-64 target has no POPCNT instruction, so descriptor_distance() compiles to four
// libgcc calls per distance. Hot BoW loops are compiled twice instead (POPCNT and baseline)
// and the CPU picks one at load time, which makes training and transform ~3x faster without
// raising the build's minimum CPU.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__POPCNT__)
#define EDGE_SLAM_POPCNT_CLONES __attribute__((target_clones("popcnt", "default")))
#else
#define EDGE_SLAM_POPCNT_CLONES
#endif
