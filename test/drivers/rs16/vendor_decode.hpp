// Reads rs16_synthetic.vendor-decode.txt, RoboSense rs_driver's decode of the
// synthetic capture: the points it printed of its first decoded packet, the
// time of that packet's last point, its scan splits and its laser table.
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace tumble::rs16::test {

struct VendorPoint {
  int index = 0;  // 32 * block + channel within the packet
  int ring = 0;   // the vendor's ring: lasers numbered by rising vertical angle
  int intensity = 0;
  double t_s = 0;
  double x = 0, y = 0, z = 0;  // NaN: no return
};

struct VendorSplit {
  int frame = 0;
  int points = 0;  // including the no-return slots
  double cloud_t_s = 0;  // time of the frame's last point
};

struct VendorDecode {
  std::vector<VendorPoint> points;
  int last_point_index = -1;
  double last_point_t_s = 0;
  std::vector<VendorSplit> splits;
  int msop_packets = -1;
  int frames = -1;
  std::array<int, 16> ring_of_laser{};            // user_chan column, row = laser
  std::array<double, 16> vertical_angle_deg{};   // vert_angle column (0.01 deg), row = laser
};

inline VendorDecode read_vendor_decode(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  VendorDecode v;
  std::string line;
  int table_row = -1;
  while (std::getline(in, line)) {
    VendorPoint p;
    char x[32], y[32], z[32];
    VendorSplit s;
    int vert = 0, horiz = 0, chan = 0;
    if (std::sscanf(line.c_str(), "i=%d ring=%d I=%d ts=%lf xyz=(%31[^,],%31[^,],%31[^)])", &p.index, &p.ring,
                    &p.intensity, &p.t_s, x, y, z) == 7) {
      p.x = std::stod(x);
      p.y = std::stod(y);
      p.z = std::stod(z);
      v.points.push_back(p);
    } else if (std::sscanf(line.c_str(), "... point %d ts=%lf", &v.last_point_index, &v.last_point_t_s) == 2) {
    } else if (std::sscanf(line.c_str(), "split: frame %d pts=%d cloud_ts=%lf", &s.frame, &s.points, &s.cloud_t_s) ==
               3) {
      v.splits.push_back(s);
    } else if (std::sscanf(line.c_str(), "msop=%d frames=%d", &v.msop_packets, &v.frames) == 2) {
    } else if (line.rfind("vert_angle", 0) == 0) {
      table_row = 0;
    } else if (table_row >= 0 && table_row < 16 && std::sscanf(line.c_str(), "%d %d %d", &vert, &horiz, &chan) == 3) {
      v.vertical_angle_deg[table_row] = vert * 0.01;
      v.ring_of_laser[table_row] = chan;
      ++table_row;
    }
  }
  if (v.points.empty() || v.splits.empty() || table_row != 16 || v.last_point_index < 0)
    throw std::runtime_error(path + ": not the vendor decode layout this test reads");
  return v;
}

}  // namespace tumble::rs16::test
