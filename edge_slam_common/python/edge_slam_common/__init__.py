"""Python helpers of edge_slam_common shared by its scripts (tum_to_bag, tum_player) and the
repository's tools and tests (scripts/, test/). Plain Python, no ROS imports at module level."""
