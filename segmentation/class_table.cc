#include "segmentation/class_table.h"

#include <array>
#include <fstream>
#include <sstream>
#include <string_view>
#include <utility>

#include "labels/cityscapes.h"

namespace rigsim {
namespace {

struct Entry {
  std::string_view network;    // the network's class name
  std::string_view cityscapes;  // the Cityscapes class it becomes
};

// ADE20K's 150 scene-parsing classes in channel order (the benchmark's objectInfo150, as
// mmsegmentation and the SegFormer and UperNet exports order them). Cityscapes has no class for
// most indoor things: fixed furniture and fittings become static, things that move dynamic, water
// terrain (unreliable, as its reflections are); structure that stays put keeps a reliable class.
constexpr std::array<Entry, 150> kAde20k = {{
    {"wall", "wall"}, {"building", "building"}, {"sky", "sky"}, {"floor", "ground"}, {"tree", "vegetation"},
    {"ceiling", "building"}, {"road", "road"}, {"bed", "static"}, {"windowpane", "building"}, {"grass", "terrain"},
    {"cabinet", "static"}, {"sidewalk", "sidewalk"}, {"person", "person"}, {"earth", "terrain"}, {"door", "building"},
    {"table", "static"}, {"mountain", "terrain"}, {"plant", "vegetation"}, {"curtain", "static"}, {"chair", "dynamic"},
    {"car", "car"}, {"water", "terrain"}, {"painting", "static"}, {"sofa", "static"}, {"shelf", "static"},
    {"house", "building"}, {"sea", "terrain"}, {"mirror", "static"}, {"rug", "static"}, {"field", "terrain"},
    {"armchair", "dynamic"}, {"seat", "static"}, {"fence", "fence"}, {"desk", "static"}, {"rock", "terrain"},
    {"wardrobe", "static"}, {"lamp", "static"}, {"bathtub", "static"}, {"railing", "fence"}, {"cushion", "dynamic"},
    {"base", "static"}, {"box", "dynamic"}, {"column", "building"}, {"signboard", "traffic sign"},
    {"chest of drawers", "static"}, {"counter", "static"}, {"sand", "terrain"}, {"sink", "static"},
    {"skyscraper", "building"}, {"fireplace", "building"}, {"refrigerator", "static"}, {"grandstand", "building"},
    {"path", "sidewalk"}, {"stairs", "ground"}, {"runway", "road"}, {"case", "static"}, {"pool table", "static"},
    {"pillow", "dynamic"}, {"screen door", "building"}, {"stairway", "ground"}, {"river", "terrain"},
    {"bridge", "bridge"}, {"bookcase", "static"}, {"blind", "static"}, {"coffee table", "static"},
    {"toilet", "static"}, {"flower", "vegetation"}, {"book", "dynamic"}, {"hill", "terrain"}, {"bench", "static"},
    {"countertop", "static"}, {"stove", "static"}, {"palm", "vegetation"}, {"kitchen island", "static"},
    {"computer", "dynamic"}, {"swivel chair", "dynamic"}, {"boat", "dynamic"}, {"bar", "static"},
    {"arcade machine", "static"}, {"hovel", "building"}, {"bus", "bus"}, {"towel", "dynamic"}, {"light", "static"},
    {"truck", "truck"}, {"tower", "building"}, {"chandelier", "static"}, {"awning", "building"},
    {"streetlight", "pole"}, {"booth", "building"}, {"television receiver", "static"}, {"airplane", "dynamic"},
    {"dirt track", "road"}, {"apparel", "dynamic"}, {"pole", "pole"}, {"land", "terrain"}, {"bannister", "fence"},
    {"escalator", "building"}, {"ottoman", "dynamic"}, {"bottle", "dynamic"}, {"buffet", "static"},
    {"poster", "static"}, {"stage", "ground"}, {"van", "car"}, {"ship", "dynamic"}, {"fountain", "static"},
    {"conveyer belt", "static"}, {"canopy", "building"}, {"washer", "static"}, {"plaything", "dynamic"},
    {"swimming pool", "terrain"}, {"stool", "dynamic"}, {"barrel", "dynamic"}, {"basket", "dynamic"},
    {"waterfall", "terrain"}, {"tent", "static"}, {"bag", "dynamic"}, {"minibike", "motorcycle"},
    {"cradle", "dynamic"}, {"oven", "static"}, {"ball", "dynamic"}, {"food", "dynamic"}, {"step", "ground"},
    {"tank", "static"}, {"trade name", "building"}, {"microwave", "static"}, {"pot", "dynamic"},
    {"animal", "dynamic"}, {"bicycle", "bicycle"}, {"lake", "terrain"}, {"dishwasher", "static"},
    {"screen", "static"}, {"blanket", "dynamic"}, {"sculpture", "static"}, {"hood", "static"}, {"sconce", "static"},
    {"vase", "dynamic"}, {"traffic light", "traffic light"}, {"tray", "dynamic"}, {"ashcan", "static"},
    {"fan", "static"}, {"pier", "bridge"}, {"crt screen", "static"}, {"plate", "dynamic"}, {"monitor", "static"},
    {"bulletin board", "static"}, {"shower", "static"}, {"radiator", "static"}, {"glass", "dynamic"},
    {"clock", "static"}, {"flag", "dynamic"},
}};

// PASCAL VOC's 20 classes and background, the classes of torchvision's pretrained segmentation
// models. Background is everything else, road and building alike: it maps to unlabeled, so that
// `--reliable unlabeled` keeps what is not a person, vehicle or animal.
constexpr std::array<Entry, 21> kVoc = {{
    {"background", "unlabeled"}, {"aeroplane", "dynamic"}, {"bicycle", "bicycle"}, {"bird", "dynamic"},
    {"boat", "dynamic"}, {"bottle", "dynamic"}, {"bus", "bus"}, {"car", "car"}, {"cat", "dynamic"},
    {"chair", "dynamic"}, {"cow", "dynamic"}, {"diningtable", "static"}, {"dog", "dynamic"}, {"horse", "dynamic"},
    {"motorbike", "motorcycle"}, {"person", "person"}, {"pottedplant", "vegetation"}, {"sheep", "dynamic"},
    {"sofa", "static"}, {"train", "train"}, {"tvmonitor", "static"},
}};

template <size_t N>
ClassTable FromEntries(const std::string& name, const std::array<Entry, N>& entries) {
  ClassTable t;
  t.name = name;
  for (const Entry& e : entries) {
    const LabelClass* c = FindClassByName(e.cityscapes);
    if (c == nullptr) throw std::logic_error("class table " + name + ": no Cityscapes class " + std::string(e.cityscapes));
    t.label_ids.push_back(c->id);
    t.channel_names.emplace_back(e.network);
  }
  return t;
}

// Channel k is the class of train id k.
ClassTable CityscapesTrainIds() {
  ClassTable t;
  t.name = "cityscapes";
  for (int train_id = 0; train_id < 19; ++train_id) {
    for (const LabelClass& c : CityscapesClasses()) {
      if (c.train_id != train_id) continue;
      t.label_ids.push_back(c.id);
      t.channel_names.emplace_back(c.name);
    }
  }
  return t;
}

std::string Trim(std::string_view s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

[[noreturn]] void Fail(const std::filesystem::path& path, const std::string& what) {
  throw SegmenterError(SegmenterErrorKind::kClassTableFile, path.string() + ": " + what);
}

const LabelClass* ParseClass(const std::string& text) {
  if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos && text.size() <= 3) {
    return FindClassById(std::stoi(text));
  }
  return FindClassByName(text);
}

}  // namespace

std::vector<std::string> BuiltinClassTableNames() { return {"cityscapes", "ade20k", "voc"}; }

ClassTable LoadClassTable(const std::string& name_or_path) {
  if (name_or_path == "cityscapes") return CityscapesTrainIds();
  if (name_or_path == "ade20k") return FromEntries("ade20k", kAde20k);
  if (name_or_path == "voc") return FromEntries("voc", kVoc);
  return ReadClassTable(name_or_path);
}

std::string BuiltinClassTableWithSize(int channels) {
  for (const std::string& name : BuiltinClassTableNames()) {
    if (LoadClassTable(name).size() == channels) return name;
  }
  return "";
}

ClassTable ReadClassTable(const std::filesystem::path& path) {
  const std::string hint = " (a class table: one line per channel, 'CHANNEL CITYSCAPES_CLASS'; or give --classes " +
                           [] {
                             std::string names;
                             for (const std::string& n : BuiltinClassTableNames()) names += (names.empty() ? "" : ", ") + n;
                             return names;
                           }() + ")";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) Fail(path, "no such class-table file" + hint);
  std::ifstream in(path);
  if (!in) Fail(path, "cannot read the class-table file");
  std::vector<std::pair<int, uint8_t>> channels;  // (channel, label id), in file order
  std::vector<std::string> names;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const size_t hash = line.find('#');
    const std::string comment = hash == std::string::npos ? "" : Trim(std::string_view(line).substr(hash + 1));
    const std::string body = Trim(std::string_view(line).substr(0, hash));
    if (body.empty()) continue;
    const std::string where = "line " + std::to_string(number) + ": ";
    std::istringstream fields(body);
    std::string channel_text;
    fields >> channel_text;
    if (channel_text.find_first_not_of("0123456789") != std::string::npos || channel_text.size() > 5) {
      Fail(path, where + "'" + channel_text + "' is not a channel number" + hint);
    }
    std::string rest;
    std::getline(fields, rest);
    const std::string class_text = Trim(rest);
    if (class_text.empty()) Fail(path, where + "channel " + channel_text + " names no class" + hint);
    const LabelClass* c = ParseClass(class_text);
    if (c == nullptr) {
      Fail(path, where + "'" + class_text + "' is no Cityscapes class" + ClassNameSuggestion(class_text) +
                     " (docs/datasets.md, 'Cityscapes classes')");
    }
    channels.emplace_back(std::stoi(channel_text), c->id);
    names.push_back(comment);
  }
  if (in.bad()) Fail(path, "cannot read the class-table file");
  if (channels.size() < 2) Fail(path, "lists " + std::to_string(channels.size()) + " channel(s); a network has 2 or more" + hint);
  ClassTable t;
  t.name = path.string();
  t.label_ids.assign(channels.size(), 0);
  t.channel_names.assign(channels.size(), "");
  std::vector<bool> seen(channels.size(), false);
  for (size_t i = 0; i < channels.size(); ++i) {
    const int ch = channels[i].first;
    if (ch >= int(channels.size())) {
      Fail(path, "channel " + std::to_string(ch) + " is out of range: the file lists " + std::to_string(channels.size()) +
                     " channels, numbered 0 to " + std::to_string(channels.size() - 1));
    }
    if (seen[ch]) Fail(path, "channel " + std::to_string(ch) + " is listed twice");
    seen[ch] = true;
    t.label_ids[ch] = channels[i].second;
    t.channel_names[ch] = names[i];
  }
  return t;
}

}  // namespace rigsim
