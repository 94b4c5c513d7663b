// ASAM MDF4 bus logging files (internal/mdf4_blocks.hpp): the CAN frames of every data group, in
// time order (a frame written more than 10 s after later ones keeps its place in the file).
//
// Read: sorted and unsorted data groups (record ids of 1, 2, 4 or 8 bytes); data in DT blocks,
// DZ blocks (deflate, transposition then deflate), DL lists and HL headers; data bytes of fixed
// length or VLSD (in a VLSD channel group of the same data group, or in SD blocks); time stamps as
// integers or floats of up to 64 bits with identity, linear, rational or value-to-value
// conversions; virtual channels (a constant bus channel, say) through their conversion. A logger's
// unfinalized file ("UnFinMF ") whose last DT block's length was never updated is read to its end.
// Channel groups of other buses (LIN, FlexRay, ...) and other channels are passed over.
//
// A damaged block (a data block that does not inflate, a list whose links lead nowhere, a channel
// group the convention cannot be read from) is one bad record naming the block's byte offset; the
// other blocks are read. A file cut short ends with one bad record.
#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <set>
#include <unordered_map>
#include <string>
#include <vector>

#include "can/canfile/internal/formats.hpp"
#include "can/canfile/internal/inflate.hpp"
#include "can/canfile/internal/mdf4_blocks.hpp"

namespace lptn::canfile {
namespace {

using namespace mdf4;
using fw::CanFrame;
using frames::FrameSource;
using fw::TimeUs;

constexpr std::uint64_t kMaxMetaBlock = 1u << 20;
constexpr std::uint64_t kMaxDataBlock = 256u << 20;
constexpr std::uint64_t kMaxLinks = 1u << 16;
constexpr int kMaxChain = 1 << 16;
constexpr std::uint32_t kMaxRecordBytes = 1u << 20;
constexpr std::size_t kMaxWaiting = 4096;  // frames waiting for their VLSD bytes
constexpr std::size_t kMaxDataBlocks = 1u << 20;
// Deflate packs at most about 1032 bytes into one; a zipped block that claims more is damaged.
constexpr std::uint64_t kMaxInflateRatio = 1040;
// Loggers write a data group's frames out of time order (a CANedge: each bus's frames in chunks,
// up to a second behind the other bus's); frames are given in time order within this window, and
// at most this many are held.
constexpr TimeUs kReorderUs = 10 * fw::kUsPerS;
constexpr std::size_t kMaxReorder = 1u << 18;

std::string at_text(std::uint64_t at) { return "byte " + std::to_string(at); }

struct Block {
  char id[3] = "";
  std::uint64_t at = 0, length = 0;
  std::vector<std::uint64_t> links;
  std::vector<std::uint8_t> data;
};

struct Conversion {
  std::uint8_t type = 0;  // 0 identity
  std::vector<double> v;
  bool supported() const { return type <= 2 || type == 4 || type == 5; }
  double operator()(double x) const {
    switch (type) {
      case 1: return v[0] + v[1] * x;
      case 2: return (v[0] * x * x + v[1] * x + v[2]) / (v[3] * x * x + v[4] * x + v[5]);
      case 4:
      case 5: {  // pairs (key, value), keys ascending
        const std::size_t n = v.size() / 2;
        if (n == 1 || std::isnan(x) || x <= v[0]) return v[1];
        if (x >= v[2 * (n - 1)]) return v[2 * n - 1];
        std::size_t i = 1;
        while (v[2 * i] < x) ++i;
        const double k0 = v[2 * i - 2], k1 = v[2 * i], y0 = v[2 * i - 1], y1 = v[2 * i + 1];
        if (type == 4) return y0 + (y1 - y0) * (x - k0) / (k1 - k0);
        return x - k0 <= k1 - x ? y0 : y1;  // nearest key
      }
      default: return x;
    }
  }
};

struct Field {
  bool present = false;
  std::uint8_t cn_type = 0, data_type = 0, bit_offset = 0;
  std::uint32_t byte_offset = 0, bit_count = 0;
  Conversion cc;
  std::uint64_t data_link = 0;
  int vlsd_group = -1;  // VLSD bytes in this channel group of the data group
  int sd = -1;          // or in this signal data stream
  bool is_virtual() const { return cn_type == kCnVirtualMaster || cn_type == kCnVirtualData; }
};

enum class Kind { other, data, remote, error };

struct Group {
  std::uint64_t at = 0, record_id = 0;
  std::uint32_t size = 0;
  bool vlsd = false;
  Kind kind = Kind::other;
  Field time, id, ide, dlc, length, bytes, bus, edl;
  std::string problem;  // non-empty: the group's frames cannot be read; reported once
  bool reported = false;
  std::uint64_t records = 0, vlsd_pos = 0;
};

struct Event {
  bool bad = false;
  TimeUs t = 0;
  CanFrame f;
  std::string channel, why;
  bool waiting = false;  // for VLSD bytes
  int vlsd_group = -1;
  std::uint64_t vlsd_offset = 0;
};

struct DataRef {
  std::uint64_t at, logical;  // file offset; offset in the data group's stream of bytes
};

// One data group: its channel groups, its data blocks read one at a time, and the events read
// from them and not yet returned.
struct DataGroupReader {
  std::uint64_t at = 0;
  std::uint8_t id_size = 0;
  std::vector<Group> groups;
  std::unordered_map<std::uint64_t, int> by_record_id;
  std::vector<DataRef> blocks;
  std::size_t next_block = 0;
  std::vector<std::uint8_t> buf;
  std::size_t pos = 0;
  std::uint64_t block_at = 0;  // the data block last loaded, for messages
  bool resync = false, ended = false, cut = false, drained = false;
  bool cut_inside = false;  // a DT or SD block the file ends inside was read up to the end
  std::string cut_note;
  std::deque<Event> out;  // in file order; frames may wait for their VLSD bytes
  std::deque<Event> bads;  // reported at once
  std::map<std::pair<TimeUs, std::uint64_t>, Event> sorted;  // frames by time, then file order
  std::uint64_t sequence = 0;
  TimeUs newest = 0;
  std::map<std::pair<int, std::uint64_t>, std::vector<std::uint8_t>> orphans;  // VLSD records before their frame
};

class Mdf4Source final : public FrameSource {
 public:
  Mdf4Source(File file, const std::filesystem::path& path) : file_(std::move(file)) {
    std::fseek(file_.get(), 0, SEEK_END);
    const long end = std::ftell(file_.get());
    size_ = end > 0 ? static_cast<std::uint64_t>(end) : 0;
    std::uint8_t id[kIdBlockSize];
    if (!read_at(0, id, sizeof id) ||
        (std::memcmp(id, kMdfMagic, 8) != 0 && std::memcmp(id, kMdfUnfinishedMagic, 8) != 0))
      throw LogError(path.string() + ": not an MDF4 file (it does not start with an MDF identification block)");
    if (id[8] != '4' || id[9] != '.')
      throw LogError(path.string() + ": MDF version " + std::string(reinterpret_cast<const char*>(id + 8), 4) +
                     ", not 4.x (lptn reads MDF4 bus logging files)");
    unfinished_ = std::memcmp(id, kMdfUnfinishedMagic, 8) == 0;
    unfin_flags_ = get<std::uint16_t>(id + 60);
    Block hd;
    if (const char* why = read_block(kIdBlockSize, "HD", 6, 32, hd))
      throw LogError(path.string() + ": " + at_text(kIdBlockSize) + ": header block (##HD): " + why);
    start_us_ = static_cast<TimeUs>(get<std::uint64_t>(hd.data.data()) / 1000);
    read_data_groups(hd.links[0]);
  }

  Status next(TimeUs& time_us, CanFrame& frame, const char*& why) override {
    if (!early_.empty()) {
      why_ = std::move(early_.front());
      early_.pop_front();
      why = why_.c_str();
      ++records_;
      return Status::bad;
    }
    DataGroupReader* best = nullptr;
    Event* best_event = nullptr;
    for (DataGroupReader& g : dgs_) {
      Event* e = front(g);
      if (!e) continue;
      if (e->bad) {
        best = &g;
        best_event = e;
        break;
      }
      if (!best || e->t < best_event->t) {
        best = &g;
        best_event = e;
      }
    }
    if (!best) return Status::end;
    Event e = std::move(*best_event);
    if (e.bad) best->bads.pop_front();
    else best->sorted.erase(best->sorted.begin());
    ++records_;
    if (e.bad) {
      why_ = std::move(e.why);
      why = why_.c_str();
      return Status::bad;
    }
    time_us = e.t;
    frame = e.f;
    channel_ = std::move(e.channel);
    return Status::frame;
  }
  std::size_t record() const override { return records_; }
  const char* record_name() const override { return "record"; }
  std::string_view channel() const override { return channel_; }

 private:
  bool read_at(std::uint64_t at, void* out, std::size_t n) {
    if (at > size_ || n > size_ - at) return false;
    if (std::fseek(file_.get(), static_cast<long>(at), SEEK_SET) != 0) return false;
    return std::fread(out, 1, n, file_.get()) == n;
  }

  // The block at `at`: "##" and one of the ids in `ids` ("DT", "DZDL": pairs), at least
  // `min_links` links and `min_data` data bytes. nullptr, or what is wrong. `to_end`: the block runs
  // to the end of the file whatever its length says. `cut`: a DT or SD block the file ends inside
  // is read up to the end, and *cut says so.
  const char* read_block(std::uint64_t at, const char* ids, std::size_t min_links, std::size_t min_data, Block& b,
                         std::uint64_t max_length = kMaxMetaBlock, bool to_end = false, bool* cut = nullptr) {
    std::uint8_t h[kHeaderSize];
    if (at == 0 || !read_at(at, h, sizeof h)) return "the link leads outside the file";
    if (h[0] != '#' || h[1] != '#') return "no block starts there (no \"##\")";
    bool known = false;
    for (const char* p = ids; p[0] && p[1]; p += 2) known |= h[2] == p[0] && h[3] == p[1];
    if (!known) return "a block of another type than expected there";
    b.id[0] = static_cast<char>(h[2]);
    b.id[1] = static_cast<char>(h[3]);
    b.at = at;
    b.length = get<std::uint64_t>(h + 8);
    const std::uint64_t links = get<std::uint64_t>(h + 16);
    if (links > kMaxLinks || b.length < kHeaderSize + 8 * links) return "block length or link count out of range";
    if (to_end && b.length < size_ - at) b.length = size_ - at;
    if (cut && b.length > size_ - at && !(b.id[0] == 'D' && b.id[1] == 'Z')) {
      b.length = size_ - at;
      *cut = true;
      if (b.length < kHeaderSize + 8 * links) return "the file ends inside the block (cut short)";
    }
    if (b.length > max_length) return "block larger than lptn reads";
    if (b.length - kHeaderSize - 8 * links < min_data || links < min_links) return "block shorter than its type's";
    if (b.length > size_ - at) return "the file ends inside the block (cut short)";
    std::vector<std::uint8_t> body(b.length - kHeaderSize);
    if (!read_at(at + kHeaderSize, body.data(), body.size())) return "the block cannot be read";
    b.links.resize(links);
    for (std::uint64_t i = 0; i < links; ++i) b.links[i] = get<std::uint64_t>(body.data() + 8 * i);
    b.data.assign(body.begin() + static_cast<std::ptrdiff_t>(8 * links), body.end());
    return nullptr;
  }

  // false (and reported) where a chain of links comes back to a block it passed: a damaged link.
  bool first_visit(std::uint64_t at, const char* block) {
    if (visited_.insert(at).second) return true;
    report(at, block, "the links lead back to a block already read (a loop)");
    return false;
  }

  void report(std::uint64_t at, const char* block, const std::string& what) {
    early_.push_back(at_text(at) + ": " + block + ": " + what + "; its frames are not read");
  }

  std::string text(std::uint64_t at) {
    Block b;
    if (at == 0 || read_block(at, "TXMD", 0, 0, b)) return "";
    std::string s(b.data.begin(), b.data.end());
    return s.substr(0, s.find('\0'));
  }

  const char* conversion(std::uint64_t at, Conversion& cc) {
    if (at == 0) return nullptr;
    Block b;
    if (const char* why = read_block(at, "CC", 4, 24, b)) return why;
    cc.type = b.data[0];
    const std::uint16_t values = get<std::uint16_t>(b.data.data() + 6);
    if (b.data.size() < 24 + 8u * values) return "conversion shorter than its values";
    for (std::uint16_t i = 0; i < values; ++i) cc.v.push_back(get_f64(b.data.data() + 24 + 8 * i));
    if (!cc.supported()) return "a conversion of a type lptn does not apply (not identity, linear, rational or "
                                "value to value)";
    if ((cc.type == 1 && cc.v.size() < 2) || (cc.type == 2 && cc.v.size() < 6) ||
        ((cc.type == 4 || cc.type == 5) && (cc.v.size() < 2 || cc.v.size() % 2 != 0)))
      return "conversion with too few values";
    for (std::size_t i = 2; (cc.type == 4 || cc.type == 5) && i + 1 < cc.v.size(); i += 2)
      if (!(cc.v[i] > cc.v[i - 2])) return "value-to-value conversion whose keys do not ascend";
    return nullptr;
  }

  const char* field(const Block& cn, Field& f) {
    const std::uint8_t* d = cn.data.data();
    f.present = true;
    f.cn_type = d[0];
    f.data_type = d[2];
    f.bit_offset = d[3];
    f.byte_offset = get<std::uint32_t>(d + 4);
    f.bit_count = get<std::uint32_t>(d + 8);
    f.data_link = cn.links[5];
    if (const char* why = conversion(cn.links[4], f.cc)) return why;
    if (f.is_virtual()) return nullptr;
    if (f.cn_type != kCnFixed && f.cn_type != kCnVlsd && f.cn_type != kCnMaster && f.cn_type != kCnSync)
      return "a channel of a type lptn does not read";
    if (f.bit_offset > 7 || f.bit_count == 0 || f.byte_offset > kMaxRecordBytes || f.bit_count > 8 * kMaxRecordBytes)
      return "channel bit offset or count out of range";
    if (f.data_type != kByteArray && f.bit_count > 64) return "numeric channel wider than 64 bits";
    if (f.data_type > kFloatBe && f.data_type != kByteArray) return "channel of a data type lptn does not read";
    if ((f.data_type == kFloatLe || f.data_type == kFloatBe) && f.bit_count != 32 && f.bit_count != 64)
      return "float channel of other than 32 or 64 bits";
    return nullptr;
  }

  void read_data_groups(std::uint64_t dg_at) {
    for (int n = 0; dg_at != 0; ++n) {
      if (n == kMaxChain) return report(dg_at, "data group (##DG)", "more data groups than lptn reads");
      Block dg;
      if (!first_visit(dg_at, "data group (##DG)")) return;
      if (const char* why = read_block(dg_at, "DG", 4, 1, dg)) return report(dg_at, "data group (##DG)", why);
      DataGroupReader r;
      r.at = dg_at;
      r.id_size = dg.data[0];
      if (r.id_size != 0 && r.id_size != 1 && r.id_size != 2 && r.id_size != 4 && r.id_size != 8)
        report(dg_at, "data group (##DG)", "record id size not 0, 1, 2, 4 or 8 bytes");
      else if (read_channel_groups(r, dg.links[1]) && dg.links[2] != 0 && collect(dg.links[2], r.blocks))
        dgs_.push_back(std::move(r));
      dg_at = dg.links[0];
    }
    // An unfinalized file's last DT block may run to the end of the file.
    if (unfinished_ && (unfin_flags_ & kUnfinDtLength)) {
      std::uint64_t last = 0;
      for (const auto& g : dgs_)
        for (const auto& b : g.blocks) last = std::max(last, b.at);
      last_dt_ = last;
    }
  }

  // The data blocks a data link leads to (DT, SD, DZ, or those a DL list or HL header lists).
  bool collect(std::uint64_t at, std::vector<DataRef>& out) {
    Block b;
    std::uint8_t h[kHeaderSize];
    if (!read_at(at, h, sizeof h) || h[0] != '#' || h[1] != '#') {
      report(at, "data link", "no block there");
      return false;
    }
    if ((h[2] == 'D' && (h[3] == 'T' || h[3] == 'Z')) || (h[2] == 'S' && h[3] == 'D')) {
      out.push_back({at, 0});
      return true;
    }
    if (h[2] == 'H' && h[3] == 'L') {
      if (const char* why = read_block(at, "HL", 1, 0, b)) {
        report(at, "header list (##HL)", why);
        return false;
      }
      at = b.links[0];
    }
    std::uint64_t index = 0;
    for (int n = 0; at != 0; ++n) {
      if (n == kMaxChain) {
        report(at, "data list (##DL)", "more lists than lptn reads");
        return !out.empty();
      }
      if (!first_visit(at, "data list (##DL)")) return !out.empty();
      if (const char* why = read_block(at, "DL", 1, 8, b)) {
        report(at, "data list (##DL)", why);
        return !out.empty();
      }
      const std::uint8_t flags = b.data[0];
      const std::uint32_t count = get<std::uint32_t>(b.data.data() + 4);
      const bool equal = flags & 1;
      if (count + 1 > b.links.size() || b.data.size() < 8 + (equal ? 8 : 8ull * count)) {
        report(at, "data list (##DL)", "more data blocks than links or offsets");
        return !out.empty();
      }
      const std::uint64_t equal_length = equal ? get<std::uint64_t>(b.data.data() + 8) : 0;
      if (out.size() + count > kMaxDataBlocks) {
        report(at, "data list (##DL)", "more data blocks than lptn reads");
        return !out.empty();
      }
      for (std::uint32_t i = 0; i < count; ++i, ++index)
        if (b.links[1 + i] != 0)
          out.push_back({b.links[1 + i], equal ? index * equal_length : get<std::uint64_t>(b.data.data() + 8 + 8 * i)});
      at = b.links[0];
    }
    return true;
  }

  bool read_channel_groups(DataGroupReader& r, std::uint64_t cg_at) {
    for (int n = 0; cg_at != 0; ++n) {
      if (n == kMaxChain) {
        report(cg_at, "channel group (##CG)", "more channel groups than lptn reads");
        break;
      }
      Block cg;
      if (!first_visit(cg_at, "channel group (##CG)")) break;
      if (const char* why = read_block(cg_at, "CG", 6, 32, cg)) {
        report(cg_at, "channel group (##CG)", why);
        break;
      }
      Group g;
      g.at = cg_at;
      g.record_id = get<std::uint64_t>(cg.data.data());
      const std::uint16_t flags = get<std::uint16_t>(cg.data.data() + 16);
      g.vlsd = flags & kCgVlsd;
      const std::uint64_t size =
          std::uint64_t{get<std::uint32_t>(cg.data.data() + 24)} + get<std::uint32_t>(cg.data.data() + 28);
      if (size > kMaxRecordBytes) g.problem = "records larger than 1 MiB";
      else g.size = static_cast<std::uint32_t>(size);
      if (!g.vlsd && g.problem.empty()) read_channels(g, cg.links[1]);
      r.groups.push_back(std::move(g));
      cg_at = cg.links[0];
    }
    for (std::size_t i = 0; i < r.groups.size(); ++i)
      if (!r.by_record_id.emplace(r.groups[i].record_id, static_cast<int>(i)).second && r.id_size != 0) {
        report(r.groups[i].at, "channel group (##CG)", "a record id another channel group of its data group has");
        return false;
      }
    if (r.id_size == 0 && r.groups.size() != 1) {
      report(r.at, "data group (##DG)", "sorted (no record ids) but not of exactly one channel group");
      return false;
    }
    if (r.id_size == 0 && r.groups[0].size == 0) {
      report(r.at, "data group (##DG)", "sorted, and its records are of no bytes");
      return false;
    }
    // VLSD data bytes: a channel group of this data group, or signal data blocks.
    for (Group& g : r.groups) {
      Field& f = g.bytes;
      if (!f.present || f.cn_type != kCnVlsd || !g.problem.empty()) continue;
      for (std::size_t i = 0; i < r.groups.size(); ++i)
        if (r.groups[i].at == f.data_link && r.groups[i].vlsd) f.vlsd_group = static_cast<int>(i);
      if (f.vlsd_group >= 0) continue;
      if (r.id_size == 0 && f.data_link != 0) {
        sd_.emplace_back();
        f.sd = static_cast<int>(sd_.size() - 1);
      } else {
        g.problem = "VLSD data bytes whose data link leads to neither signal data nor a VLSD channel group";
      }
    }
    return true;
  }

  void read_channels(Group& g, std::uint64_t cn_at) {
    auto fail = [&g](std::uint64_t at, const std::string& why) {
      if (g.problem.empty()) g.problem = "channel (##CN) at " + at_text(at) + ": " + why;
    };
    Field* event_fields[] = {&g.id, &g.ide, &g.dlc, &g.length, &g.bytes, &g.bus, &g.edl};
    for (int n = 0; cn_at != 0 && n < kMaxChain; ++n) {
      Block cn;
      if (!visited_.insert(cn_at).second) return fail(cn_at, "the links lead back to a channel already read (a loop)");
      if (const char* why = read_block(cn_at, "CN", 8, 72, cn)) return fail(cn_at, why);
      const std::string name = text(cn.links[2]);
      const std::uint8_t type = cn.data[0], sync = cn.data[1];
      if ((type == kCnMaster || type == kCnVirtualMaster) && sync == 1) {
        if (const char* why = field(cn, g.time)) return fail(cn_at, why);
      } else if ((name == "CAN_DataFrame" || name == "CAN_RemoteFrame" || name == "CAN_ErrorFrame") &&
                 cn.links[1] != 0) {
        g.kind = name == "CAN_DataFrame" ? Kind::data : name == "CAN_RemoteFrame" ? Kind::remote : Kind::error;
        std::uint64_t member_at = cn.links[1];
        for (int m = 0; member_at != 0 && m < kMaxChain; ++m) {
          Block member;
          if (!visited_.insert(member_at).second)
            return fail(member_at, "the links lead back to a channel already read (a loop)");
          if (const char* why = read_block(member_at, "CNCA", 8, 0, member)) return fail(member_at, why);
          if (member.id[1] != 'N' || member.data.size() < 72)
            return fail(member_at, "a composition other than of channels");
          const std::string full = text(member.links[2]);
          const std::string leaf = full.substr(full.rfind('.') + 1);
          static const char* const kLeaves[] = {"ID", "IDE", "DLC", "DataLength", "DataBytes", "BusChannel", "EDL"};
          for (std::size_t i = 0; i < std::size(kLeaves); ++i)
            if (leaf == kLeaves[i])
              if (const char* why = field(member, *event_fields[i])) return fail(member_at, why);
          member_at = member.links[0];
        }
      }
      cn_at = cn.links[0];
    }
    if (g.kind == Kind::other) return;
    if (!g.time.present) return fail(g.at, "bus events without a time master channel");
    if (g.kind != Kind::error && !g.id.present) return fail(g.at, "CAN frames without their .ID");
    if (g.kind == Kind::data && !g.bytes.present) return fail(g.at, "CAN data frames without their .DataBytes");
    if (g.kind == Kind::data && !g.dlc.present && !g.length.present)
      return fail(g.at, "CAN data frames without .DLC or .DataLength");
    if (g.bytes.present && g.bytes.cn_type == kCnVlsd && g.bytes.bit_count > 64)
      return fail(g.at, "a VLSD offset wider than 64 bits");
    for (const Field* f : {&g.time, &g.id, &g.ide, &g.dlc, &g.length, &g.bytes, &g.bus, &g.edl})
      if (f->present && !f->is_virtual() && f->byte_offset + (f->bit_offset + std::uint64_t{f->bit_count} + 7) / 8 > g.size)
        return fail(g.at, "a channel beyond the record's bytes");
  }

  // A data block's bytes (DT, SD, or DZ inflated): nullptr, or what is wrong.
  // A DT or SD block the file ends inside: its bytes up to the end, and *cut says so.
  const char* load(std::uint64_t at, std::vector<std::uint8_t>& out, bool* cut = nullptr) {
    Block b;
    if (const char* why = read_block(at, "DTSDDZ", 0, 0, b, kMaxDataBlock + 64, at == last_dt_ && last_dt_ != 0, cut))
      return why;
    if (b.id[0] != 'D' || b.id[1] != 'Z') {
      out = std::move(b.data);
      return nullptr;
    }
    if (b.data.size() < 24) return "zipped block shorter than its header";
    const std::uint8_t* d = b.data.data();
    const std::uint8_t zip = d[2];
    const std::uint32_t columns = get<std::uint32_t>(d + 4);
    const std::uint64_t original = get<std::uint64_t>(d + 8), zipped = get<std::uint64_t>(d + 16);
    if (zip != kDeflate && zip != kTransposeDeflate) return "zipped by a method other than deflate or transposition";
    if (original > kMaxDataBlock) return "zipped block larger than lptn reads unzipped";
    if (zipped > b.data.size() - 24) return "zipped block shorter than its zipped length";
    if (original > zipped * kMaxInflateRatio + 64) return "zipped block claims more bytes than deflate packs";
    std::vector<std::uint8_t> inflated(original);
    if (!inflater_.inflate_exactly(d + 24, zipped, inflated.data(), original))
      return "zipped data does not inflate to its stated length (corrupt)";
    if (zip == kTransposeDeflate && columns > 0) {
      out.resize(inflated.size());
      transpose(inflated.data(), out.data(), inflated.size(), columns, false);
    } else {
      out = std::move(inflated);
    }
    return nullptr;
  }

  enum class Got { ok, end, bad };

  // n bytes at r.buf[r.pos], loading blocks as needed; `bad`: a block failed (why_ says which).
  Got need(DataGroupReader& r, std::size_t n) {
    while (r.buf.size() - r.pos < n) {
      if (r.next_block == r.blocks.size()) return Got::end;
      const DataRef ref = r.blocks[r.next_block++];
      std::vector<std::uint8_t> bytes;
      bool cut = false;
      if (const char* why = load(ref.at, bytes, &cut)) {
        why_ = at_text(ref.at) + ": data block: " + why + "; its records are not read" + blocks_after_end(r);
        r.buf.clear();
        r.pos = 0;
        r.resync = true;
        return Got::bad;
      }
      r.buf.erase(r.buf.begin(), r.buf.begin() + static_cast<std::ptrdiff_t>(r.pos));
      r.pos = 0;
      if (r.resync) {  // after a lost block: the stream goes on where this block's offset says
        r.resync = false;
        r.buf.clear();
        const std::uint64_t size = r.id_size == 0 && !r.groups.empty() ? r.groups[0].size : 0;
        if (size > 0 && ref.logical % size != 0) r.pos = static_cast<std::size_t>(size - ref.logical % size);
        if (r.pos > bytes.size()) r.pos = bytes.size();
      }
      r.block_at = ref.at;
      r.buf.insert(r.buf.end(), bytes.begin(), bytes.end());
      if (cut) r.cut_note = blocks_after_end(r);
      r.cut_inside = r.cut_inside || cut;
    }
    return Got::ok;
  }

  // A file cut short: the data blocks listed after its end are dropped, and go with the message
  // of the block it ends in (", nor those of the 3 data blocks after the file's end").
  std::string blocks_after_end(DataGroupReader& r) {
    const auto beyond = std::remove_if(r.blocks.begin() + static_cast<std::ptrdiff_t>(r.next_block), r.blocks.end(),
                                       [this](const DataRef& b) { return b.at >= size_; });
    const auto lost = r.blocks.end() - beyond;
    r.blocks.erase(beyond, r.blocks.end());
    if (lost == 0) return "";
    return ", nor those of the " + std::to_string(lost) + " data block" + (lost > 1 ? "s" : "") + " after the file's end";
  }

  void push_bad(DataGroupReader& r, std::string why) {
    Event e;
    e.bad = true;
    e.why = std::move(why);
    r.out.push_back(std::move(e));
  }

  // One record of `r` onto r.out (or, for VLSD bytes, into the frame waiting for them). false at the end.
  bool read_record(DataGroupReader& r) {
    const std::size_t have = r.buf.size() - r.pos;
    Got got = need(r, std::max<std::size_t>(r.id_size, 1));
    if (got == Got::bad) return push_bad(r, why_), true;
    if (got == Got::end) {
      if (have > 0 || r.cut_inside) {
        r.cut = true;
        push_bad(r, at_text(r.block_at) + ": data block: the file ends inside " + (have > 0 ? "a record" : "the block") +
                        " (cut short)" + r.cut_note);
        r.buf.clear();
        r.pos = 0;
      }
      return false;
    }
    std::uint64_t record_id = 0;
    for (std::size_t i = 0; i < r.id_size; ++i) record_id |= std::uint64_t{r.buf[r.pos + i]} << (8 * i);
    int gi = r.id_size == 0 ? 0 : -1;
    if (gi < 0)
      if (const auto it = r.by_record_id.find(record_id); it != r.by_record_id.end()) gi = it->second;
    if (gi < 0) {
      push_bad(r, at_text(r.block_at) + ": data block: record id " + std::to_string(record_id) +
                      " of no channel group; the rest of the block is not read");
      r.buf.clear();
      r.pos = 0;
      r.resync = true;
      return true;
    }
    Group& g = r.groups[static_cast<std::size_t>(gi)];
    std::size_t size = g.size;
    if (g.vlsd) {
      if ((got = need(r, r.id_size + 4)) != Got::ok) return got == Got::bad ? (push_bad(r, why_), true) : truncated(r);
      const std::uint32_t length = get<std::uint32_t>(r.buf.data() + r.pos + r.id_size);
      if (length > kMaxRecordBytes) {
        push_bad(r, at_text(r.block_at) + ": data block: VLSD record longer than 1 MiB; the rest of the block is not read");
        r.buf.clear();
        r.pos = 0;
        r.resync = true;
        return true;
      }
      size = 4 + length;
    }
    if ((got = need(r, r.id_size + size)) != Got::ok) return got == Got::bad ? (push_bad(r, why_), true) : truncated(r);
    const std::uint8_t* rec = r.buf.data() + r.pos + r.id_size;
    r.pos += r.id_size + size;
    if (g.vlsd) {
      vlsd_record(r, gi, g.vlsd_pos, rec + 4, size - 4);
      g.vlsd_pos += size;
      return true;
    }
    const std::uint64_t index = g.records++;
    if (g.kind == Kind::other) return true;
    if (!g.problem.empty()) {
      if (!g.reported) push_bad(r, at_text(g.at) + ": channel group (##CG): " + g.problem + "; its frames are not read");
      g.reported = true;
      return true;
    }
    decode(r, g, rec, index);
    return true;
  }

  bool truncated(DataGroupReader& r) {
    r.cut = true;
    push_bad(r, at_text(r.block_at) + ": data block: the file ends inside a record (cut short)" + r.cut_note);
    r.buf.clear();
    r.pos = 0;
    return false;
  }

  static std::uint64_t raw_bits(const std::uint8_t* rec, const Field& f) {
    const std::uint32_t bytes = (f.bit_offset + f.bit_count + 7) / 8;
    const bool big = f.data_type == kUintBe || f.data_type == kIntBe || f.data_type == kFloatBe;
    // Up to 9 bytes (64 bits from bit offset 7): the low 8, then the ninth's bits.
    std::uint64_t low = 0, ninth = 0;
    for (std::uint32_t i = 0; i < bytes; ++i) {
      const std::uint64_t byte = rec[f.byte_offset + (big ? bytes - 1 - i : i)];
      if (i < 8) low |= byte << (8 * i);
      else ninth = byte;
    }
    std::uint64_t v = low >> f.bit_offset;
    if (f.bit_offset > 0) v |= ninth << (64 - f.bit_offset);
    return f.bit_count >= 64 ? v : v & ((std::uint64_t{1} << f.bit_count) - 1);
  }

  static double value(const std::uint8_t* rec, const Field& f, std::uint64_t index) {
    double x;
    if (f.is_virtual()) {
      x = static_cast<double>(index);
    } else {
      const std::uint64_t raw = raw_bits(rec, f);
      if (f.data_type == kFloatLe || f.data_type == kFloatBe) {
        if (f.bit_count == 32) {
          float fl;
          const auto bits = static_cast<std::uint32_t>(raw);
          std::memcpy(&fl, &bits, sizeof fl);
          x = fl;
        } else {
          std::memcpy(&x, &raw, sizeof x);
        }
      } else if ((f.data_type == kIntLe || f.data_type == kIntBe) && f.bit_count < 64 && (raw >> (f.bit_count - 1)) & 1) {
        x = static_cast<double>(static_cast<std::int64_t>(raw | ~((std::uint64_t{1} << f.bit_count) - 1)));
      } else if (f.data_type == kIntLe || f.data_type == kIntBe) {
        x = static_cast<double>(static_cast<std::int64_t>(raw));
      } else {
        x = static_cast<double>(raw);
      }
    }
    return f.cc(x);
  }

  static bool whole(double v, double max) { return std::isfinite(v) && v >= 0 && v <= max && v == std::floor(v); }

  void decode(DataGroupReader& r, const Group& g, const std::uint8_t* rec, std::uint64_t index) {
    Event e;
    const auto bad = [&](const char* why) {
      push_bad(r, at_text(r.block_at) + ": data block: record " + std::to_string(index + 1) + " of the channel group at " +
                      at_text(g.at) + ": " + why);
    };
    const double s = value(rec, g.time, index);
    if (!std::isfinite(s) || std::fabs(s) > 1e10) return bad("time stamp not a number or beyond three centuries");
    e.t = start_us_ + static_cast<TimeUs>(std::llround(s * 1e6));
    if (e.t < 0) return bad("time stamp before 1970");
    CanFrame& f = e.f;
    const double id = g.id.present ? value(rec, g.id, index) : 0;
    if (!whole(id, 0x1FFFFFFF)) return bad("frame id not a whole number of up to 29 bits");
    f.id = static_cast<std::uint32_t>(id);
    f.extended = g.ide.present ? value(rec, g.ide, index) != 0 : f.id > 0x7FF;
    if (!f.extended && f.id > 0x7FF && g.kind != Kind::error) return bad("standard frame id above 0x7FF");
    f.error = g.kind == Kind::error;
    f.remote = g.kind == Kind::remote;
    f.fd = g.edl.present && value(rec, g.edl, index) != 0;
    if (g.bus.present) {
      const double bus = value(rec, g.bus, index);
      if (!whole(bus, 1e9)) return bad("bus channel not a whole number");
      e.channel = std::to_string(static_cast<long long>(bus));
    } else {
      e.channel = "1";
    }
    if (f.error) {
      r.out.push_back(std::move(e));
      return;
    }
    double length = -1;
    if (g.length.present) length = value(rec, g.length, index);
    else if (g.dlc.present) {
      const double dlc = value(rec, g.dlc, index);
      if (!whole(dlc, 15)) return bad("DLC not 0..15");
      length = f.fd ? kFdLengths[static_cast<int>(dlc)] : std::min(dlc, 8.0);
    }
    if (!whole(length, 64)) return bad("data length not 0..64");
    if (!f.fd && length > 8) {
      if (g.edl.present || f.remote) length = 8;  // classic: a DLC above 8 means 8 bytes
      else f.fd = true;
    }
    f.len = static_cast<std::uint8_t>(length);
    if (f.fd && f.len > 8 && kFdLengths[fd_length_code(f.len)] != f.len) return bad("CAN FD data length no DLC gives");
    if (f.remote || f.len == 0) {
      r.out.push_back(std::move(e));
      return;
    }
    const Field& b = g.bytes;
    if (b.cn_type != kCnVlsd) {
      if (b.is_virtual() || b.data_type != kByteArray) return bad("data bytes not a byte array");
      if (b.bit_count / 8 < f.len) return bad("data length beyond the record's data bytes");
      std::memcpy(f.data, rec + b.byte_offset, f.len);
      r.out.push_back(std::move(e));
      return;
    }
    const std::uint64_t offset = raw_bits(rec, b);
    if (b.sd >= 0) {
      const std::vector<std::uint8_t>* sd = signal_data(b);
      if (!sd) return bad("its VLSD data bytes are in signal data that cannot be read");
      if (offset > sd->size() || sd->size() - offset < 4) return bad("VLSD offset beyond the signal data");
      const std::uint32_t n = get<std::uint32_t>(sd->data() + offset);
      if (n > sd->size() - offset - 4 || n < f.len) return bad("VLSD data bytes shorter than the data length");
      std::memcpy(f.data, sd->data() + offset + 4, f.len);
      r.out.push_back(std::move(e));
      return;
    }
    e.vlsd_group = b.vlsd_group;
    e.vlsd_offset = offset;
    const auto orphan = r.orphans.find({e.vlsd_group, offset});
    if (orphan != r.orphans.end()) {
      if (!fill(e, orphan->second)) return bad("VLSD data bytes shorter than the data length");
      r.orphans.erase(orphan);
    } else {
      e.waiting = true;
    }
    r.out.push_back(std::move(e));
  }

  static bool fill(Event& e, const std::vector<std::uint8_t>& bytes) {
    e.waiting = false;
    if (bytes.size() < e.f.len) {
      e.bad = true;
      e.why = "VLSD data bytes shorter than the frame's data length";
      return false;
    }
    std::memcpy(e.f.data, bytes.data(), e.f.len);
    return true;
  }

  void vlsd_record(DataGroupReader& r, int gi, std::uint64_t offset, const std::uint8_t* p, std::size_t n) {
    std::vector<std::uint8_t> bytes(p, p + n);
    for (Event& e : r.out)
      if (e.waiting && e.vlsd_group == gi && e.vlsd_offset == offset) {
        if (!fill(e, bytes)) e.why = at_text(r.block_at) + ": data block: " + e.why;
        return;
      }
    if (r.orphans.size() >= kMaxWaiting) r.orphans.erase(r.orphans.begin());
    r.orphans[{gi, offset}] = std::move(bytes);
  }

  const std::vector<std::uint8_t>* signal_data(const Field& b) {
    auto& sd = sd_[static_cast<std::size_t>(b.sd)];
    if (!sd.loaded) {
      sd.loaded = true;
      std::vector<DataRef> blocks;
      if (!collect(b.data_link, blocks)) return nullptr;
      for (const DataRef& ref : blocks) {
        std::vector<std::uint8_t> bytes;
        if (load(ref.at, bytes) || sd.bytes.size() + bytes.size() > kMaxDataBlock) {
          sd.ok = false;
          return nullptr;
        }
        sd.bytes.insert(sd.bytes.end(), bytes.begin(), bytes.end());
      }
      sd.ok = true;
    }
    return sd.ok ? &sd.bytes : nullptr;
  }

  // Reads r's records until the first event in file order is ready (its VLSD bytes found) and
  // moves it on: to r.bads or r.sorted. false: nothing more in r.
  bool pull(DataGroupReader& r) {
    for (;;) {
      while (!r.ended && (r.out.empty() || r.out.front().waiting)) {
        if (r.out.size() > kMaxWaiting) break;
        if (!read_record(r)) r.ended = true;
      }
      if (r.out.empty()) return false;
      Event& e = r.out.front();
      if (e.waiting) {  // its VLSD bytes never came
        if (r.cut && r.ended) {  // the file was cut before them: the one message says so
          r.out.pop_front();
          continue;
        }
        e.waiting = false;
        e.bad = true;
        e.why = at_text(r.block_at) + ": data block: a frame whose VLSD data bytes are missing";
      }
      if (e.bad) {
        r.bads.push_back(std::move(e));
      } else {
        r.newest = std::max(r.newest, e.t);
        const std::pair<TimeUs, std::uint64_t> key{e.t, r.sequence++};
        // Mostly in order: then the hint makes the insertion constant time.
        if (r.sorted.empty() || r.sorted.rbegin()->first < key) r.sorted.emplace_hint(r.sorted.end(), key, std::move(e));
        else r.sorted.emplace(key, std::move(e));
      }
      r.out.pop_front();
      return true;
    }
  }

  // r's next event: a bad one at once; else its earliest frame once no frame still to come can
  // be earlier (within the reordering window). nullptr: nothing more in r.
  Event* front(DataGroupReader& r) {
    for (;;) {
      if (!r.bads.empty()) return &r.bads.front();
      if (!r.sorted.empty() && (r.drained || r.newest - r.sorted.begin()->first.first > kReorderUs ||
                                r.sorted.size() > kMaxReorder))
        return &r.sorted.begin()->second;
      if (r.drained) return nullptr;
      if (!pull(r)) r.drained = true;
    }
  }

  struct SignalData {
    bool loaded = false, ok = false;
    std::vector<std::uint8_t> bytes;
  };

  File file_;
  Inflater inflater_;
  std::uint64_t size_ = 0, last_dt_ = 0;
  bool unfinished_ = false;
  std::uint16_t unfin_flags_ = 0;
  TimeUs start_us_ = 0;
  std::vector<DataGroupReader> dgs_;
  std::vector<SignalData> sd_;
  std::deque<std::string> early_;
  std::set<std::uint64_t> visited_;  // data groups, channel groups, channels and data lists read
  std::string why_, channel_;
  std::size_t records_ = 0;
};

}  // namespace

std::unique_ptr<frames::FrameSource> make_mdf4_source(File file, const std::filesystem::path& path) {
  return std::make_unique<Mdf4Source>(std::move(file), path);
}

}  // namespace lptn::canfile
