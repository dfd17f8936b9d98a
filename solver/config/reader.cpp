#include "config/reader.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "io/text_file.hpp"

namespace narwhal {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  const bool above_lo = lo_open ? v > lo : v >= lo;
  const bool below_hi = hi_open ? v < hi : v <= hi;
  return above_lo && below_hi;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    if (!lo_open && !hi_open) return fmt::format("between {:.15g} and {:.15g}", lo, hi);
    return fmt::format("in {}{:.15g}, {:.15g}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]");
  }
  if (has_lo) return fmt::format("{} {:.15g}", lo_open ? ">" : ">=", lo);
  if (has_hi) return fmt::format("{} {:.15g}", hi_open ? "<" : "<=", hi);
  return "finite";
}

ConfigReader::ConfigReader(const std::string& path) : file_(path) {
  std::string text;
  try {
    text = read_text_file(path);
  } catch (const Error& e) {
    fail("case file: {}", e.what());
  }
  parse(text);
}

ConfigReader::ConfigReader(const std::string& text, const std::string& display_name) : file_(display_name) {
  parse(text);
}

void ConfigReader::parse(const std::string& text) {
  text_ = text;
  try {
    root_ = toml::parse(text_, file_);
  } catch (const toml::parse_error& e) {
    fail("{}:{}:{}: TOML syntax error: {}", file_, e.source().begin.line, e.source().begin.column, e.description());
  }
}

namespace {

void lay_over(toml::table& under, const toml::table& over) {
  for (const auto& [k, v] : over) {
    toml::node* existing = under.get(k.str());
    if (existing && existing->is_table() && v.is_table())
      lay_over(*existing->as_table(), *v.as_table());
    else
      under.insert_or_assign(k.str(), v);
  }
}

// Every key reached through tables of `t` (arrays are leaves), dotted, under `prefix`.
void collect_keys(const toml::table& t, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& [k, v] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (v.is_table())
      collect_keys(*v.as_table(), key, out);
    else
      out.push_back(key);
  }
}

}  // namespace

std::vector<ConfigReader::BaseFile> ConfigReader::merge_base(const std::string& base_dir) {
  base_dir_ = base_dir;
  const toml::node* b = root_.get("base");
  if (!b) return {};
  note("base");
  // Down the chain of bases (each path relative to the directory of the file naming it),
  // then each file laid over the one below it.
  std::vector<toml::table> chain;
  std::vector<BaseFile> bases;
  std::filesystem::path dir = base_dir;
  toml::table over = std::move(root_);
  for (const toml::node* next = b; next;) {
    const auto name = next->value<std::string>();
    if (!name) error("base", "expected a string: the path of the case this one is laid over");
    const std::filesystem::path path = std::filesystem::path(*name).is_absolute()
                                           ? std::filesystem::path(*name)
                                           : dir / *name;
    const std::string shown = path.lexically_normal().string();
    const auto seen = [&](const BaseFile& f) { return f.path == shown; };
    if (std::any_of(bases.begin(), bases.end(), seen) || bases.size() == 4)
      error("base", fmt::format("the chain of bases through '{}' loops or is deeper than 4", shown));
    std::string text;
    try {
      text = read_text_file(shown);
    } catch (const Error& e) {
      error("base", e.what());
    }
    try {
      chain.push_back(toml::parse(text, shown));
    } catch (const toml::parse_error& e) {
      fail("{}:{}:{}: TOML syntax error: {}", shown, e.source().begin.line, e.source().begin.column, e.description());
    }
    bases.push_back({shown, std::move(text)});
    dir = path.parent_path();
    next = chain.back().get("base");
  }
  over.erase("base");
  // Which folder each key's file lies in, the nearest file that sets it winning.
  for (std::size_t i = chain.size(); i-- > 0;) {
    chain[i].erase("base");
    std::vector<std::string> keys;
    collect_keys(chain[i], "", keys);
    const std::string folder = std::filesystem::path(bases[i].path).parent_path().string();
    for (const std::string& k : keys) folder_of_[k] = folder.empty() ? "." : folder;
  }
  std::vector<std::string> own;
  collect_keys(over, "", own);
  for (const std::string& k : own) folder_of_.erase(k);
  root_ = std::move(chain.back());
  for (std::size_t i = chain.size() - 1; i-- > 0;) lay_over(root_, chain[i]);
  lay_over(root_, over);
  return bases;
}

void ConfigReader::apply_override(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) fail("{}: override '{}': expected key=value", file_, assignment);
  std::string key = assignment.substr(0, eq);
  key.erase(key.find_last_not_of(' ') + 1);
  folder_of_.erase(key);  // an override's file names are the case's (relative to its folder)
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + assignment.substr(eq + 1));
  } catch (const toml::parse_error& e) {
    fail("{}: override '{}': the value is not valid TOML: {}", file_, assignment, e.description());
  }
  toml::table* t = &root_;
  std::size_t start = 0;
  std::string walked;  // the dotted path so far, for messages
  for (std::size_t dot; (dot = key.find('.', start)) != std::string::npos; start = dot + 1) {
    std::string part = key.substr(start, dot - start);
    std::optional<std::size_t> index;
    if (const auto open = part.find('['); open != std::string::npos) {
      std::size_t v = 0;
      const auto close = part.find(']', open);
      const char* first = part.data() + open + 1;
      const char* last = part.data() + (close == std::string::npos ? part.size() : close);
      const auto [end, ec] = std::from_chars(first, last, v);
      if (close != part.size() - 1 || ec != std::errc() || end != last)
        fail("{}: override '{}': '{}' is not name[index] with a whole-number index", file_, assignment, part);
      index = v;
      part.resize(open);
    }
    walked += (walked.empty() ? "" : ".") + part;
    toml::node* n = t->get(part);
    if (index) {
      toml::array* a = n ? n->as_array() : nullptr;
      if (!a || !a->is_array_of_tables())
        fail("{}: override '{}': the case has no array of tables '{}' ([[{}]])", file_, assignment, walked, walked);
      if (*index >= a->size())
        fail("{}: override '{}': the case has {} [[{}]] table(s), valid indices 0 to {}", file_, assignment, a->size(), walked,
             a->size() - 1);
      t = (*a)[*index].as_table();
      walked += fmt::format("[{}]", *index);
      continue;
    }
    if (!n) n = &t->insert_or_assign(part, toml::table{}).first->second;
    t = n->as_table();
    if (!t) fail("{}: override '{}': '{}' is not a table", file_, assignment, walked);
  }
  t->insert_or_assign(key.substr(start), *parsed.get("v"));
}

void ConfigReader::error(const std::string& key, const std::string& message) const {
  fail("{}: key '{}': {}", file_, key, message);
}

void ConfigReader::note(const std::string& key) const { known_.insert(key); }

const toml::node* ConfigReader::find(const std::string& key) const {
  note(key);
  return root_.at_path(key).node();
}

bool ConfigReader::has(const std::string& key) const { return find(key) != nullptr; }

namespace {
const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date/time";
  }
}
std::string toml_text(const toml::node& n) {
  std::ostringstream os;
  n.visit([&](const auto& v) { os << v; });
  return os.str();
}
}  // namespace

Real ConfigReader::number(const std::string& key, const std::string& what, const Range& range) const {
  const toml::node* n = find(key);
  if (!n) error(key, "missing required key (expected " + what + ")");
  const auto v = n->value<double>();
  if (!v) error(key, std::string("expected ") + what + ", got " + type_name(*n));
  if (!std::isfinite(*v)) error(key, fmt::format("expected {}, got {} (not a finite number)", what, *v));
  if (!range.contains(*v)) error(key, fmt::format("expected {} {}, got {}", what, range.describe(), *v));
  return *v;
}

Real ConfigReader::number_or(const std::string& key, Real fallback, const std::string& what,
                             const Range& range) const {
  return has(key) ? number(key, what, range) : fallback;
}

int ConfigReader::integer(const std::string& key, const std::string& what, const Range& range) const {
  const toml::node* n = find(key);
  if (!n) error(key, "missing required key (expected " + what + ")");
  if (!n->is_integer()) error(key, std::string("expected ") + what + " (an integer), got " + type_name(*n));
  // Checked on the 64-bit value TOML holds, before any narrowing (2^32 + 1 must not become 1).
  const int64_t v = *n->value<int64_t>();
  const Range r{std::max<double>(range.lo, std::numeric_limits<int>::min()),
                std::min<double>(range.hi, std::numeric_limits<int>::max()), range.lo_open, range.hi_open};
  if (!r.contains(static_cast<double>(v)))
    error(key, fmt::format("expected {} (an integer {}), got {}", what, r.describe(), v));
  return static_cast<int>(v);
}

int ConfigReader::integer_or(const std::string& key, int fallback, const std::string& what,
                             const Range& range) const {
  return has(key) ? integer(key, what, range) : fallback;
}

std::string ConfigReader::string(const std::string& key, const std::string& what) const {
  const toml::node* n = find(key);
  if (!n) error(key, "missing required key (expected " + what + ")");
  if (auto v = n->value<std::string>()) return *v;
  error(key, std::string("expected ") + what + " (a string), got " + type_name(*n));
}

std::string ConfigReader::file_path(const std::string& key, const std::string& what) const {
  const std::string f = string(key, what);
  if (std::filesystem::path(f).is_absolute()) return f;
  const auto from = folder_of_.find(key);
  return (std::filesystem::path(from == folder_of_.end() ? base_dir_ : from->second) / f).string();
}

std::string ConfigReader::string_or(const std::string& key, const std::string& fallback,
                                    const std::string& what) const {
  return has(key) ? string(key, what) : fallback;
}

bool ConfigReader::boolean_or(const std::string& key, bool fallback, const std::string& what) const {
  const toml::node* n = find(key);
  if (!n) return fallback;
  if (auto v = n->value<bool>()) return *v;
  error(key, std::string("expected ") + what + " (true or false), got " + type_name(*n));
}

std::vector<Real> ConfigReader::numbers(const std::string& key, const std::string& what, std::size_t count,
                                       const Range& range) const {
  const toml::node* n = find(key);
  if (!n) error(key, "missing required key (expected " + what + ")");
  const toml::array* a = n->as_array();
  const std::string shape = fmt::format("an array of {} numbers", count);
  if (!a || a->size() != count) error(key, "expected " + what + " as " + shape);
  std::vector<Real> v(count);
  for (std::size_t m = 0; m < count; ++m) {
    auto x = (*a)[m].value<double>();
    if (!x) error(key, "expected " + what + " as " + shape);
    if (!std::isfinite(*x)) error(key, fmt::format("expected {}: entry {} is {} (not a finite number)", what, m + 1, *x));
    if (!range.contains(*x))
      error(key, fmt::format("expected {}: entry {} is {}, must be {}", what, m + 1, *x, range.describe()));
    v[m] = *x;
  }
  return v;
}

std::vector<Real> ConfigReader::number_list(const std::string& key, const std::string& what, const Range& range) const {
  const toml::node* n = find(key);
  if (!n) error(key, "missing required key (expected " + what + ")");
  const toml::array* a = n->as_array();
  if (!a || a->empty()) error(key, "expected " + what + " as an array of one or more numbers");
  return numbers(key, what, a->size(), range);
}

Vec3 ConfigReader::vec3(const std::string& key, const std::string& what, const Range& range) const {
  const std::vector<Real> v = numbers(key, what, 3, range);
  return Vec3(v[0], v[1], v[2]);
}

std::vector<std::string> ConfigReader::strings_or(const std::string& key, const std::vector<std::string>& fallback,
                                                  const std::string& what) const {
  const toml::node* n = find(key);
  if (!n) return fallback;
  const toml::array* a = n->as_array();
  if (!a) error(key, "expected " + what + " as an array of strings");
  std::vector<std::string> v;
  for (const auto& e : *a) {
    auto x = e.value<std::string>();
    if (!x) error(key, "expected " + what + " as an array of strings");
    v.push_back(*x);
  }
  return v;
}

Vec3 ConfigReader::vec3_or(const std::string& key, const Vec3& fallback, const std::string& what,
                           const Range& range) const {
  return has(key) ? vec3(key, what, range) : fallback;
}

std::pair<int, int> ConfigReader::index_range(const std::string& key, const std::string& what, int max_end) const {
  const toml::node* n = find(key);
  if (!n) error(key, "missing required key (expected " + what + ")");
  const toml::array* a = n->as_array();
  std::optional<int64_t> first, end;
  if (a && a->size() == 2) {
    first = (*a)[0].value_exact<int64_t>();
    end = (*a)[1].value_exact<int64_t>();
  }
  if (!first || !end) error(key, fmt::format("expected {} as two integers, got {}", what, toml_text(*n)));
  if (!(*first >= 0 && *first < *end && *end <= max_end))
    error(key, fmt::format("expected {} with 0 <= first < end <= {}, got [{}, {}]", what, max_end, *first, *end));
  return {static_cast<int>(*first), static_cast<int>(*end)};
}

std::vector<std::string> ConfigReader::subtables(const std::string& key) const {
  std::vector<std::string> names;
  const toml::node* n = find(key);
  if (!n) return names;
  const toml::table* t = n->as_table();
  if (!t) error(key, "expected a table");
  for (const auto& [k, v] : *t) {
    if (!v.is_table()) error(key + "." + std::string(k.str()), "expected a table");
    names.emplace_back(k.str());
  }
  return names;
}

std::size_t ConfigReader::array_size(const std::string& key) const {
  const toml::node* n = find(key);
  if (!n) return 0;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables()) error(key, "expected an array of tables ([[" + key + "]])");
  return a->size();
}

void ConfigReader::reject_unknown_keys() const {
  std::vector<std::string> unknown;
  std::function<void(const toml::table&, const std::string&)> walk = [&](const toml::table& t,
                                                                         const std::string& prefix) {
    for (const auto& [k, v] : t) {
      const std::string path = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
      if (const toml::table* sub = v.as_table()) {
        walk(*sub, path);
      } else if (const toml::array* arr = v.as_array(); arr && arr->is_array_of_tables()) {
        for (std::size_t i = 0; i < arr->size(); ++i)
          walk(*(*arr)[i].as_table(), path + "[" + std::to_string(i) + "]");
      } else if (!known_.count(path)) {
        unknown.push_back(path);
      }
    }
  };
  walk(root_, "");
  if (unknown.empty()) return;
  std::string msg;
  for (const auto& u : unknown) {
    std::string best;
    std::size_t best_d = 4;  // suggest only close matches
    for (const auto& k : known_) {
      const std::size_t d = edit_distance(u, k);
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    msg += fmt::format("\n  unknown key '{}'", u);
    if (!best.empty()) msg += fmt::format(" (did you mean '{}'?)", best);
  }
  fail("{}: {}", file_, msg.substr(3));
}

}  // namespace narwhal
