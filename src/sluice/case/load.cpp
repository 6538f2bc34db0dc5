#include "sluice/case/load.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "sluice/case/case_error.hpp"
#include "sluice/case/checks.hpp"
#include "sluice/case/meshes.hpp"
#include "sluice/case/motions.hpp"
#include "sluice/case/param_fields.hpp"
#include "sluice/case/suggest.hpp"
#include "sluice/case/toml_values.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice {

namespace {

// "file:line:column" of a node, or just the file for a node without a position.
std::string where(const std::string& source, const toml::node& n) {
  const auto& region = n.source();
  if (region.begin.line == 0) return source;
  return fmt::format("{}:{}:{}", source, region.begin.line, region.begin.column);
}

std::string describe_shape(const Region& r) { return std::string(name_of(r.shape, shape_names)); }
std::string describe_shape(const Probe& p) { return std::string(name_of(p.type, probe_type_names)) + " probe"; }
std::string describe_shape(const FloatingSpec&) { return "floating body"; }
std::string describe_shape(const MotionLawSpec& m) {
  if (m.law == MotionLawType::wave)
    return fmt::format("wave law with spectrum = \"{}\"", name_of(m.spectrum, wave_spectrum_names));
  return std::string(name_of(m.law, motion_law_names)) + " law";
}

template <class Owner>
std::vector<std::string> keys_of(const std::vector<Param<Owner>>& params) {
  std::vector<std::string> keys;
  for (const auto& p : params) keys.push_back(p.key);
  return keys;
}

// Reads the tables of one case file into a case of the file's dimension.
class Loader {
 public:
  Loader(const std::string& source, int dimension) : source_(source), dimension_(dimension) {
    set_defaults(c_, case_params(), dimension);
    c_.dimension = dimension;
  }

  void read(const std::string& name, const toml::node& node) {
    const auto section = std::find_if(case_sections().begin(), case_sections().end(),
                                      [&](const Section& s) { return s.name == name; });
    if (section == case_sections().end()) fail_unknown_section(name, node);
    if (section->is_array) read_items(name, node);
    else read_section(name, node);
  }

  [[nodiscard]] const Case& result() const { return c_; }

 private:
  [[noreturn]] void fail_unknown_section(const std::string& name, const toml::node& node) const {
    if (!node.is_table() && !node.is_array()) {  // a key written before any [section] header
      const auto near = closest_match(name, all_keys());
      throw CaseError(fmt::format("{}: key '{}' is outside any section; {}", where(source_, node), printable(name),
                                  near ? fmt::format("did you mean '{}' (key '{}' under [{}])?", *near,
                                                     near->substr(near->find('.') + 1),
                                                     near->substr(0, near->find('.')))
                                       : std::string("keys belong under a [section] header; see `sluice init`")));
    }
    std::vector<std::string> section_names;
    for (const auto& s : case_sections()) section_names.push_back(s.name);
    const auto near = closest_match(name, section_names);
    throw CaseError(fmt::format("{}: unknown section '{}'{}", where(source_, node), printable(name),
                                near ? fmt::format("; did you mean '{}'?", *near)
                                     : fmt::format("; expected one of: {}", fmt::join(section_names, ", "))));
  }

  // [name] with keys name.key.
  void read_section(const std::string& name, const toml::node& node) {
    const toml::table* table = node.as_table();
    if (table == nullptr)
      throw CaseError(fmt::format("{}: '{}' must be a section [{}] holding keys", where(source_, node), name, name));
    for (const auto& [sub, value] : *table) {
      const std::string key = name + "." + std::string(sub.str());
      if (name == "tank" && (sub.str() == "translation" || sub.str() == "rotation")) {
        read_tank_law(value, sub.str() == "rotation");
        continue;
      }
      const auto* p = find_param(case_params(), key);
      if (p == nullptr) fail_unknown_key(where(source_, value), key, all_keys());
      assign(c_, *p, value, where(source_, value), key, dimension_);
    }
  }

  // The [[name]] tables, in file order.
  void read_items(const std::string& name, const toml::node& node) {
    const toml::array* items = node.as_array();
    if (items == nullptr || !items->is_array_of_tables())
      throw CaseError(fmt::format("{}: '{}' must be written as [[{}]] tables", where(source_, node), name, name));
    std::size_t index = 0;
    for (const auto& item : *items) {
      const toml::table& t = *item.as_table();
      if (name == "water") c_.water.push_back(read_item(t, region_params(), name, index));
      else if (name == "wall") c_.walls.push_back(read_wall(t, index));
      else c_.probes.push_back(read_item(t, probe_params(), name, index));
      ++index;
    }
  }

  // [tank.translation] or [tank.rotation]: a law of the tank's own motion.
  void read_tank_law(const toml::node& node, bool rotation) {
    const char* part = rotation ? "rotation" : "translation";
    const toml::table* law = node.as_table();
    if (law == nullptr)
      throw CaseError(fmt::format("{}: tank.{} must be a table, [tank.{}], holding its law and the law's keys",
                                  where(source_, node), part, part));
    (rotation ? c_.tank_rotation : c_.tank_translation) =
        read_item(*law, motion_law_params(rotation), fmt::format("tank.{}", part), 0);
  }

  // A [[wall]]: a region with a name, and its [wall.translation] and [wall.rotation] tables.
  [[nodiscard]] Region read_wall(const toml::table& t, std::size_t index) const {
    toml::table keys = t;
    keys.erase("translation");
    keys.erase("rotation");
    keys.erase("floating");
    Region wall = read_item(keys, wall_params(), "wall", index);
    if (const toml::node* node = t.get("floating")) {
      const toml::table* table = node->as_table();
      if (table == nullptr)
        throw CaseError(fmt::format("{}: wall[{}].floating must be a table, [wall.floating] after the [[wall]], holding "
                                    "the body's mass and the keys of its motion",
                                    where(source_, *node), index));
      wall.floating = read_item(*table, floating_params(), "wall.floating", index);
      wall.floats = true;
    }
    if (wall.name.empty()) wall.name = fmt::format("wall{}", index + 1);
    for (const bool rotation : {false, true}) {
      const char* part = rotation ? "rotation" : "translation";
      const toml::node* node = t.get(part);
      if (node == nullptr) continue;
      const toml::table* law = node->as_table();
      if (law == nullptr)
        throw CaseError(fmt::format("{}: wall[{}].{} must be a table, [wall.{}] after the [[wall]], holding its law "
                                    "and the law's keys",
                                    where(source_, *node), index, part, part));
      (rotation ? wall.rotation : wall.translation) =
          read_item(*law, motion_law_params(rotation), fmt::format("wall.{}", part), index);
    }
    return wall;
  }

  template <class Owner>
  Owner read_item(const toml::table& t, const std::vector<Param<Owner>>& params, const std::string& section,
                  std::size_t index) const {
    Owner item{};
    set_defaults(item, params, dimension_);
    std::set<std::string> given;
    for (const auto& [k, node] : t) {
      const std::string key(k.str());
      const auto* p = find_param(params, key);
      if (p == nullptr) {
        const auto candidates = keys_of(params);
        const auto near = closest_match(key, candidates);
        throw CaseError(fmt::format("{}: unknown key '{}' in {}{}", where(source_, node), printable(key),
                                    section.find('.') == std::string::npos ? fmt::format("[[{}]]", section)
                                                                          : item_label(section, index),
                                    near ? fmt::format("; did you mean '{}'?", *near)
                                         : fmt::format("; expected one of: {}", fmt::join(candidates, ", "))));
      }
      assign(item, *p, node, where(source_, node), key_path(section, index, key), dimension_);
      given.insert(key);
    }
    check_item_keys(item, given, t, params, section, index);
    return item;
  }

  // How a message names a key of an item: water[0].max, wall[1].translation.speed; a key of the tank's
  // motion, tank.rotation.period.
  static std::string key_path(const std::string& section, std::size_t index, const std::string& key) {
    if (section.starts_with("tank.")) return fmt::format("{}.{}", section, key);
    return fmt::format("{}[{}].{}", section, index, key);
  }

  // How a message names an item: "[[wall]] number 2", or for a table inside one (a wall's motion law,
  // section "wall.translation") "[wall.translation] of [[wall]] number 2".
  static std::string item_label(const std::string& section, std::size_t index) {
    if (section.starts_with("tank.")) return fmt::format("[{}]", section);
    const auto dot = section.find('.');
    if (dot == std::string::npos) return fmt::format("[[{}]] number {}", section, index + 1);
    return fmt::format("[{}] of [[{}]] number {}", section, section.substr(0, dot), index + 1);
  }

  // Keys that only some items use (a box's min and max, a polygon's points) are required by those
  // items and refused by the others, so that nothing given is silently ignored.
  template <class Owner>
  void check_item_keys(const Owner& item, const std::set<std::string>& given, const toml::table& t,
                       const std::vector<Param<Owner>>& params, const std::string& section, std::size_t index) const {
    for (const auto& p : params) {
      const bool required =
          std::holds_alternative<std::monostate>(p.default_value) || (p.applies && p.applies(item) && !p.optional);
      if (required && !given.contains(p.key))
        throw CaseError(fmt::format("{}: {} has no '{}' ({}); expected {}", where(source_, t),
                                    item_label(section, index), p.key, p.description, expectation(p, dimension_)));
      if (p.applies && !p.applies(item) && given.contains(p.key))
        throw CaseError(fmt::format("{}: {} gives '{}', which a {} does not use ({})", where(source_, t),
                                    item_label(section, index), p.key, describe_shape(item), p.description));
    }
  }

  const std::string& source_;
  int dimension_;
  Case c_;
};

toml::table parse_toml(std::string_view text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw CaseError(fmt::format("{}:{}:{}: not valid TOML: {}", source, b.line, b.column, e.description()));
  }
}

// The dimension is read first: the defaults (gravity) and every vector's length follow from it.
int dimension_of(const toml::table& root, const std::string& source) {
  const toml::node* d = root.at_path("domain.dimension").node();
  if (d == nullptr) return 2;
  Case c;
  assign(c, *find_param(case_params(), "domain.dimension"), *d, where(source, *d), "domain.dimension", 2);
  return c.dimension;
}

}  // namespace

Case parse_case(std::string_view toml_text, const std::string& source, const std::string& mesh_directory) {
  const toml::table root = parse_toml(toml_text, source);
  Loader loader(source, dimension_of(root, source));
  for (const auto& [name, node] : root) loader.read(std::string(name.str()), node);
  Case c = loader.result();
  c.mesh_directory = mesh_directory;
  load_meshes(c, source);
  load_motion_files(c, source);
  validate_case(c, source);
  return c;
}

Case load_case_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw CaseError(fmt::format("{}: no such case file (and no built-in case of that name; see `sluice cases`)",
                                path.string()));
  if (std::filesystem::is_directory(path, ec))
    throw CaseError(fmt::format("{}: is a directory; expected a case file (.toml)", path.string()));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CaseError(fmt::format("{}: cannot be read", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  // Mesh files are found beside the case file.
  const std::filesystem::path directory = std::filesystem::absolute(path, ec).parent_path();
  return parse_case(text.str(), path.string(), ec ? std::string(".") : directory.string());
}

}  // namespace sluice
