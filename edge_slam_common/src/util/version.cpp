// Library version string, so tools can print what they were built from.
namespace edge_slam {
const char* version() { return "0.1.0"; }
}  // namespace edge_slam
