#include "sluice/case/case_template.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <vector>

#include "sluice/case/param_fields.hpp"
#include "sluice/case/parameter_table.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice {

namespace {

class TemplateWriter {
 public:
  explicit TemplateWriter(const Case& c) : c_(c) {}

  std::string write() {
    out_ += "# sluice case file (TOML). Every key is listed with its unit, default and allowed range;\n";
    out_ += "# delete a key to use its default. Run it with:  sluice run <this file>\n";
    for (const auto& s : case_sections()) {
      out_ += "\n";
      comment(s.description, "");
      if (!s.is_array) write_section(s);
      else if (s.name == "water") write_items(s, c_.water, region_params());
      else if (s.name == "wall") write_walls(s);
      else write_items(s, c_.probes, probe_params());
    }
    return out_;
  }

 private:
  void comment(const std::string& text, const std::string& indent) { out_ += indent + "# " + text + "\n"; }

  // Its description, then "unit: ... | default: ... | allowed: ...".
  template <class Owner>
  void describe(const Param<Owner>& p, const std::string& indent) {
    comment(p.description, indent);
    std::vector<std::string> facts;
    if (!p.unit.empty()) facts.push_back("unit: " + p.unit);
    const ParamValue& def = default_in(p, c_.dimension);
    facts.push_back(std::holds_alternative<std::monostate>(def) ? std::string("required")
                                                                : "default: " + format_value(def, c_.dimension));
    facts.push_back("allowed: " + expectation(p, c_.dimension));
    comment(fmt::format("{}", fmt::join(facts, " | ")), indent);
  }

  // [name] and its keys, each with its description.
  void write_section(const Section& s) {
    out_ += fmt::format("[{}]\n", s.name);
    for (const auto& p : case_params()) {
      if (p.key.rfind(s.name + ".", 0) != 0 || (p.only_3d && c_.dimension != 3)) continue;
      describe(p, "");
      out_ += fmt::format("{} = {}\n", p.key.substr(s.name.size() + 1), format_value(current_value(c_, p), c_.dimension));
    }
    if (s.name == "tank") write_tank_motion();
  }

  // A moving tank's [tank.translation] and [tank.rotation] tables (the keys of a wall's, described with
  // the walls').
  void write_tank_motion() {
    comment("The tank's own walls move when [tank.translation] or [tank.rotation] gives a law: the keys of a "
            "wall's [wall.translation] and [wall.rotation] (see [[wall]] below).",
            "");
    for (const bool rotation : {false, true}) {
      const MotionLawSpec& law = rotation ? c_.tank_rotation : c_.tank_translation;
      if (law.law == MotionLawType::none) continue;
      out_ += fmt::format("[tank.{}]\n", rotation ? "rotation" : "translation");
      for (const auto& p : motion_law_params(rotation))
        if ((p.applies == nullptr || p.applies(law)) && !(p.only_3d && c_.dimension != 3))
          out_ += fmt::format("{} = {}\n", p.key, format_value(current_value(law, p), c_.dimension));
    }
  }

  // The keys of [[name]] described once in comments, then each item with the keys it uses.
  template <class Owner>
  void write_items(const Section& s, const std::vector<Owner>& items, const std::vector<Param<Owner>>& params) {
    comment(fmt::format("Keys of each [[{}]]:", s.name), "");
    for (const auto& p : params) {
      out_ += fmt::format("#   {}:\n", p.key);
      describe(p, "#     ");
    }
    if (items.empty()) comment(fmt::format("(this case has no [[{}]] entries)", s.name), "");
    for (const auto& item : items) {
      out_ += fmt::format("[[{}]]\n", s.name);
      for (const auto& p : params)
        if (p.applies == nullptr || p.applies(item))
          out_ += fmt::format("{} = {}\n", p.key, format_value(current_value(item, p), c_.dimension));
    }
  }

  // [[wall]] items as the others, each followed by its [wall.translation] and [wall.rotation] tables
  // when it moves; their keys described once after the walls' own.
  void write_walls(const Section& s) {
    comment("Keys of each [[wall]]:", "");
    for (const auto& p : wall_params()) {
      out_ += fmt::format("#   {}:\n", p.key);
      describe(p, "#     ");
    }
    for (const bool rotation : {false, true}) {
      const char* part = rotation ? "rotation" : "translation";
      comment(fmt::format("A moving wall's [wall.{}] table, after its [[wall]]; its keys:", part), "");
      for (const auto& p : motion_law_params(rotation)) {
        if (p.only_3d && c_.dimension != 3) continue;
        out_ += fmt::format("#   {}:\n", p.key);
        describe(p, "#     ");
      }
    }
    comment("A floating wall's [wall.floating] table, after its [[wall]] (it then has no motion laws); its keys:", "");
    for (const auto& p : floating_params()) {
      out_ += fmt::format("#   {}:\n", p.key);
      describe(p, "#     ");
    }
    if (c_.walls.empty()) comment(fmt::format("(this case has no [[{}]] entries)", s.name), "");
    for (const auto& wall : c_.walls) {
      out_ += "[[wall]]\n";
      for (const auto& p : wall_params())
        if (p.applies == nullptr || p.applies(wall))
          out_ += fmt::format("{} = {}\n", p.key, format_value(current_value(wall, p), c_.dimension));
      for (const bool rotation : {false, true}) {
        const MotionLawSpec& law = rotation ? wall.rotation : wall.translation;
        if (law.law == MotionLawType::none) continue;
        out_ += fmt::format("[wall.{}]\n", rotation ? "rotation" : "translation");
        for (const auto& p : motion_law_params(rotation))
          if ((p.applies == nullptr || p.applies(law)) && !(p.only_3d && c_.dimension != 3))
            out_ += fmt::format("{} = {}\n", p.key, format_value(current_value(law, p), c_.dimension));
      }
      if (wall.floats) {
        out_ += "[wall.floating]\n";
        for (const auto& p : floating_params()) {
          // An empty list is the default (none given), which TOML's [] would not read back as.
          const ParamValue v = current_value(wall.floating, p);
          const auto* numbers = std::get_if<std::vector<double>>(&v);
          const auto* names = std::get_if<std::vector<std::string>>(&v);
          if ((numbers && numbers->empty()) || (names && names->empty())) continue;
          out_ += fmt::format("{} = {}\n", p.key, format_value(v, c_.dimension));
        }
      }
    }
  }

  const Case& c_;
  std::string out_;
};

}  // namespace

std::string case_template(const Case& c) { return TemplateWriter(c).write(); }

}  // namespace sluice
