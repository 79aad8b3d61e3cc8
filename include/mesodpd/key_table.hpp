// Declared configuration keys: a model states the keys of its config section next to its code (name,
// type, default, allowed range, one-line meaning) by binding each to a member of its spec struct. The
// TOML reader, the range checks of validate(spec), the refusal of unknown keys and the key tables of
// docs/config.md (`mesodpd keys --markdown`) all follow from these declarations.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "mesodpd/config_error.hpp"

namespace mesodpd {

// A problem with one key of a spec. `key` is the full key as the TOML schema spells it
// ("pair.override[1].rd", "system.box[2]"), `value` the offending value as text (empty when the key
// is absent), `why` what is wrong or allowed. what() is "key = value: why" ("key: why" without a
// value); the TOML reader prefixes the key's file:line:col.
class SpecError : public ConfigError {
 public:
  SpecError(std::string key, std::string value, std::string why);
  const std::string& value() const { return value_; }
  const std::string& why() const { return why_; }

 private:
  std::string value_, why_;
};

namespace keys {

constexpr double kInf = std::numeric_limits<double>::infinity();

// An allowed interval for a real value; non-finite values are always outside.
struct Range {
  double lo = -kInf, hi = kInf;
  bool lo_closed = true, hi_closed = true;

  bool contains(double v) const {
    return std::isfinite(v) && (lo_closed ? v >= lo : v > lo) && (hi_closed ? v <= hi : v < hi);
  }
  // The refusal, as validate() words it ("must be > 0", "must be in (0, 10]").
  std::string text() const;
  // The interval for the docs ("> 0", "(0, 10]", "finite").
  std::string doc() const;
};
inline constexpr Range kPositive{0.0, kInf, false, true};
inline constexpr Range kNonNegative{0.0, kInf, true, true};
inline constexpr Range kFinite{};
inline constexpr Range kCutoff{0.0, 10.0, false, true};

// Allowed integers, lo <= v <= hi.
struct IntRange {
  long long lo = std::numeric_limits<long long>::min();
  long long hi = std::numeric_limits<long long>::max();
  std::string doc() const;
};

[[noreturn]] void fail(const std::string& key, std::string value, std::string why);
std::string show(double v);
void check(const std::string& key, double v, Range r);
void check_int(const std::string& key, long long v, IntRange r);

// How a declared key is held in its struct. `Choice` maps words to the integer value of an enum (or an
// axis index); `Custom` keys are read and checked by hand-written code of their model (shapes, lists
// that resolve names) and are declared only for the unknown-key check and the docs.
template <class T>
struct Choice {
  std::vector<std::pair<std::string, int>> options;
  std::function<void(T&, int)> set;
  std::function<int(const T&)> get;
};
struct Custom {};
template <class T>
using Binding = std::variant<double T::*, std::optional<double> T::*, int T::*, std::uint64_t T::*, bool T::*,
                             std::string T::*, std::array<double, 3> T::*, std::optional<std::array<double, 3>> T::*,
                             std::array<int, 3> T::*, std::array<bool, 3> T::*, std::vector<std::string> T::*,
                             Choice<T>, Custom>;

// One value of a selecting choice (a solid's `shape`, a bond type's `style`) and the keys of its table
// it reads: `required` ones must be written, `optional` ones may be; every other key that some value of
// the selector reads is refused.
struct Variant {
  int value;
  std::vector<std::string> required, optional;
};

// One row of a key table, as docs/config.md shows it.
struct KeyDoc {
  std::string name, type, default_text, allowed, meaning;
};

template <class T>
struct Key {
  std::string name;
  Binding<T> binding;
  std::optional<Range> range;        // numbers (each element of a vector)
  std::optional<IntRange> int_range;  // integers
  bool required = false;
  std::string missing_hint;           // added to "missing required key" (" (three positive box lengths)")
  std::string noun;                   // array of 3 integers: "not a whole number of <noun>"
  std::string unit;                   // shown after the value in `mesodpd check`'s summary ("r_c")
  KeyDoc doc;                         // type/default/allowed filled from the binding unless given
  // A selecting choice: the keys each of its values reads, and the refusals of the others ("{key}" is
  // the selector's full name, "{value}" its value as written).
  std::vector<Variant> variants;
  std::string unused_why, needed_hint;
};

// Text of values for messages and docs.
std::string doc_number(double v);  // 1.0, 0.04, 1000.0
std::string quoted_words(const std::vector<std::string_view>& words, std::string_view quote, std::string_view sep);

// The declared keys of one TOML table, bound to the members of T. Declaration order is the order of
// the range checks and of the docs' rows.
template <class T>
class KeyTable {
 public:
  // `path`: the table's full name ("integrator", "analysis.rdf", "species" for [[species]]).
  explicit KeyTable(std::string path) : path_(std::move(path)) {}

  KeyTable& number(std::string name, double T::*m, Range r, std::string meaning) {
    return add(std::move(name), m, "number", std::move(meaning)).with_range(r);
  }
  KeyTable& number(std::string name, std::optional<double> T::*m, Range r, std::string meaning) {
    return add(std::move(name), m, "number", std::move(meaning)).with_range(r);
  }
  KeyTable& integer(std::string name, int T::*m, IntRange r, std::string meaning) {
    return add(std::move(name), m, "integer", std::move(meaning)).with_int_range(r);
  }
  KeyTable& integer(std::string name, std::uint64_t T::*m, IntRange r, std::string meaning) {
    return add(std::move(name), m, "integer", std::move(meaning)).with_int_range(r);
  }
  KeyTable& boolean(std::string name, bool T::*m, std::string meaning) {
    return add(std::move(name), m, "boolean", std::move(meaning));
  }
  KeyTable& string(std::string name, std::string T::*m, std::string meaning) {
    return add(std::move(name), m, "string", std::move(meaning));
  }
  KeyTable& vec3(std::string name, std::array<double, 3> T::*m, Range r, std::string meaning) {
    return add(std::move(name), m, "array of 3 numbers", std::move(meaning)).with_range(r);
  }
  // Three numbers that may be left out (the member stays empty).
  KeyTable& vec3(std::string name, std::optional<std::array<double, 3>> T::*m, Range r, std::string meaning) {
    return add(std::move(name), m, "array of 3 numbers", std::move(meaning)).with_range(r);
  }
  // Three whole numbers (an integer-valued float is accepted), each in `r`; `noun` names what they count
  // in the refusal of a fraction ("element 1 is 2.5, not a whole number of bins").
  KeyTable& ints3(std::string name, std::array<int, 3> T::*m, IntRange r, std::string noun, std::string meaning) {
    add(std::move(name), m, "array of 3 integers", std::move(meaning)).with_int_range(r);
    keys_.back().noun = std::move(noun);
    return *this;
  }
  KeyTable& bool3(std::string name, std::array<bool, 3> T::*m, std::string meaning) {
    return add(std::move(name), m, "array of 3 booleans", std::move(meaning));
  }
  KeyTable& strings(std::string name, std::vector<std::string> T::*m, std::string meaning) {
    return add(std::move(name), m, "array of strings", std::move(meaning));
  }
  // A string that must be one of `options`, stored as the enum E (or int) member m.
  template <class E>
  KeyTable& choice(std::string name, E T::*m, std::vector<std::pair<std::string, E>> options, std::string meaning) {
    Choice<T> c;
    for (const auto& [word, value] : options) c.options.emplace_back(word, static_cast<int>(value));
    c.set = [m](T& t, int v) { t.*m = static_cast<E>(v); };
    c.get = [m](const T& t) { return static_cast<int>(t.*m); };
    return add(std::move(name), std::move(c), "string", std::move(meaning));
  }
  // An axis "x", "y" or "z", stored as 0, 1, 2.
  KeyTable& axis(std::string name, int T::*m, std::string meaning) {
    KeyTable& t = choice<int>(std::move(name), m, {{"x", 0}, {"y", 1}, {"z", 2}}, std::move(meaning));
    t.keys_.back().int_range = IntRange{0, 2};
    return t;
  }
  // A key read and checked by its model's own code; declared for the unknown-key check and the docs.
  KeyTable& custom(std::string name, std::string type, std::string default_text, std::string allowed,
                   std::string meaning) {
    add(std::move(name), Custom{}, std::move(type), std::move(meaning));
    keys_.back().doc.default_text = std::move(default_text);
    keys_.back().doc.allowed = std::move(allowed);
    return *this;
  }

  // Modifiers of the key declared last.
  KeyTable& required(std::string hint = {}) {
    keys_.back().required = true;
    keys_.back().missing_hint = std::move(hint);
    keys_.back().doc.default_text = "required";
    return *this;
  }
  KeyTable& default_text(std::string text) {
    keys_.back().doc.default_text = std::move(text);
    return *this;
  }
  KeyTable& type_text(std::string text) {
    keys_.back().doc.type = std::move(text);
    return *this;
  }
  KeyTable& allowed(std::string text) {
    keys_.back().doc.allowed = std::move(text);
    return *this;
  }
  KeyTable& unit(std::string text) {
    keys_.back().unit = std::move(text);
    return *this;
  }
  // The choice declared last selects which keys of the table are read (variant() for each of its values);
  // a key that another value reads is refused with `unused_why`, a missing required one reported with
  // `needed_hint` ("{key}": the selector's full name, "{value}": its value as written).
  KeyTable& selects(std::string unused_why, std::string needed_hint) {
    keys_.back().unused_why = std::move(unused_why);
    keys_.back().needed_hint = std::move(needed_hint);
    return *this;
  }
  template <class E>
  KeyTable& variant(E value, std::vector<std::string> required, std::vector<std::string> optional = {}) {
    keys_.back().variants.push_back(Variant{static_cast<int>(value), std::move(required), std::move(optional)});
    return *this;
  }

  // Sub-tables ([analysis.rdf] inside [analysis]) and other names the table accepts.
  KeyTable& subtable(std::string name) {
    subtables_.push_back(std::move(name));
    return *this;
  }

  const std::string& path() const { return path_; }
  const std::vector<Key<T>>& keys() const { return keys_; }
  // Every key the table accepts, declared keys first.
  std::vector<std::string_view> names() const {
    std::vector<std::string_view> out;
    for (const auto& k : keys_) out.push_back(k.name);
    for (const auto& s : subtables_) out.push_back(s);
    return out;
  }
  const Key<T>* find(std::string_view name) const {
    for (const auto& k : keys_)
      if (k.name == name) return &k;
    return nullptr;
  }
  // The selecting choice of the table (variant()), if any.
  const Key<T>* selector() const {
    for (const auto& k : keys_)
      if (!k.variants.empty()) return &k;
    return nullptr;
  }
  // Whether `name` is read by only some values of the selector.
  bool selected(std::string_view name) const {
    const Key<T>* sel = selector();
    if (!sel) return false;
    for (const Variant& v : sel->variants)
      for (const auto* list : {&v.required, &v.optional})
        for (const std::string& n : *list)
          if (n == name) return true;
    return false;
  }
  // Whether the key `name` is read for the value `t` holds (always, unless the selector leaves it out).
  bool used(const T& t, std::string_view name) const {
    if (!selected(name)) return true;
    const Key<T>* sel = selector();
    const int value = std::get<Choice<T>>(sel->binding).get(t);
    for (const Variant& v : sel->variants)
      if (v.value == value)
        for (const auto* list : {&v.required, &v.optional})
          for (const std::string& n : *list)
            if (n == name) return true;
    return false;
  }

  // The range checks of validate(): every declared range, in declaration order, on the values of `t`;
  // `prefix` is the full name of the table ("analysis.rdf", "species[2]").
  void check(const std::string& prefix, const T& t) const;

  // The rows of this table for docs/config.md.
  std::vector<KeyDoc> docs() const;

  // The values of `t` that differ from the struct's defaults, as "key = value" (with the key's unit),
  // in declaration order: `mesodpd check`'s summary. Custom keys and keys the selector leaves out are
  // not shown.
  std::vector<std::string> set_values(const T& t) const;

 private:
  KeyTable& add(std::string name, Binding<T> b, std::string type, std::string meaning) {
    Key<T> k;
    k.name = std::move(name);
    k.binding = std::move(b);
    k.doc = KeyDoc{k.name, std::move(type), {}, {}, std::move(meaning)};
    keys_.push_back(std::move(k));
    return *this;
  }
  KeyTable& with_range(Range r) {
    keys_.back().range = r;
    return *this;
  }
  KeyTable& with_int_range(IntRange r) {
    keys_.back().int_range = r;
    return *this;
  }

  // "`\"plane\"`: `point`, `normal`; `\"pillars\"`: `lattice`, ... (optional `axis`)": what each value reads.
  std::string variants_doc(const Key<T>& sel) const {
    const auto& words = std::get<Choice<T>>(sel.binding).options;
    std::string out;
    for (const Variant& v : sel.variants) {
      std::string word;
      for (const auto& [w, value] : words)
        if (value == v.value) word = w;
      std::vector<std::string_view> req(v.required.begin(), v.required.end()), opt(v.optional.begin(), v.optional.end());
      out += (out.empty() ? "" : "; ") + quoted_words({word}, "\"", "") + ": " + quoted_words(req, "", ", ");
      if (!opt.empty()) out += (req.empty() ? "optional " : ", optional ") + quoted_words(opt, "", ", ");
    }
    return out;
  }
  // The values of the selector that require `name`, as words ("fene, wlc").
  std::string needed_by(std::string_view name) const {
    const Key<T>* sel = selector();
    std::string out;
    for (const Variant& v : sel->variants)
      for (const std::string& n : v.required)
        if (n == name)
          for (const auto& [w, value] : std::get<Choice<T>>(sel->binding).options)
            if (value == v.value) out += (out.empty() ? "" : ", ") + w;
    return out;
  }

  std::string path_;
  std::vector<Key<T>> keys_;
  std::vector<std::string> subtables_;
};


template <class T>
void KeyTable<T>::check(const std::string& prefix, const T& t) const {
  const auto full = [&](const Key<T>& k) { return prefix.empty() ? k.name : prefix + "." + k.name; };
  for (const Key<T>& k : keys_) {
    if (!used(t, k.name)) continue;
    std::visit(
        [&](const auto& b) {
          using B = std::decay_t<decltype(b)>;
          if constexpr (std::is_same_v<B, double T::*>) {
            if (k.range) keys::check(full(k), t.*b, *k.range);
          } else if constexpr (std::is_same_v<B, std::optional<double> T::*>) {
            if (k.range && (t.*b)) keys::check(full(k), *(t.*b), *k.range);
          } else if constexpr (std::is_same_v<B, int T::*> || std::is_same_v<B, std::uint64_t T::*>) {
            if (k.int_range) check_int(full(k), static_cast<long long>(t.*b), *k.int_range);
          } else if constexpr (std::is_same_v<B, std::array<double, 3> T::*>) {
            if (k.range)
              for (std::size_t d = 0; d < 3; ++d) keys::check(full(k) + "[" + std::to_string(d) + "]", (t.*b)[d], *k.range);
          } else if constexpr (std::is_same_v<B, std::optional<std::array<double, 3>> T::*>) {
            if (k.range && (t.*b))
              for (std::size_t d = 0; d < 3; ++d) keys::check(full(k) + "[" + std::to_string(d) + "]", (*(t.*b))[d], *k.range);
          } else if constexpr (std::is_same_v<B, std::array<int, 3> T::*>) {
            if (k.int_range)
              for (std::size_t d = 0; d < 3; ++d) check_int(full(k) + "[" + std::to_string(d) + "]", (t.*b)[d], *k.int_range);
          } else if constexpr (std::is_same_v<B, Choice<T>>) {
            // An enum set in C++ is always one of its values; an axis index is not.
            if (k.int_range) {
              const int v = b.get(t);
              if (v < k.int_range->lo || v > k.int_range->hi)
                fail(full(k), std::to_string(v), "must be one of \"x\", \"y\", \"z\" (0, 1, 2)");
            }
          }
        },
        k.binding);
  }
}

template <class T>
std::vector<KeyDoc> KeyTable<T>::docs() const {
  const T defaults{};
  std::vector<KeyDoc> out;
  for (const Key<T>& k : keys_) {
    KeyDoc d = k.doc;
    std::string def, allowed;
    std::visit(
        [&](const auto& b) {
          using B = std::decay_t<decltype(b)>;
          if constexpr (std::is_same_v<B, double T::*>) {
            def = doc_number(defaults.*b);
          } else if constexpr (std::is_same_v<B, std::optional<double> T::*>) {
            def = (defaults.*b) ? doc_number(*(defaults.*b)) : "none";
          } else if constexpr (std::is_same_v<B, int T::*> || std::is_same_v<B, std::uint64_t T::*>) {
            def = std::to_string(defaults.*b);
          } else if constexpr (std::is_same_v<B, bool T::*>) {
            def = (defaults.*b) ? "true" : "false";
          } else if constexpr (std::is_same_v<B, std::string T::*>) {
            def = (defaults.*b).empty() ? "none" : "`\"" + (defaults.*b) + "\"`";
          } else if constexpr (std::is_same_v<B, std::array<double, 3> T::*>) {
            const auto& v = defaults.*b;
            def = "[" + doc_number(v[0]) + ", " + doc_number(v[1]) + ", " + doc_number(v[2]) + "]";
          } else if constexpr (std::is_same_v<B, std::optional<std::array<double, 3>> T::*>) {
            const auto& v = defaults.*b;
            def = v ? "[" + doc_number((*v)[0]) + ", " + doc_number((*v)[1]) + ", " + doc_number((*v)[2]) + "]" : "none";
          } else if constexpr (std::is_same_v<B, std::array<int, 3> T::*>) {
            const auto& v = defaults.*b;
            def = "[" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) + "]";
          } else if constexpr (std::is_same_v<B, std::array<bool, 3> T::*>) {
            const auto& v = defaults.*b;
            def = std::string("[") + (v[0] ? "true" : "false") + ", " + (v[1] ? "true" : "false") + ", " +
                  (v[2] ? "true" : "false") + "]";
          } else if constexpr (std::is_same_v<B, std::vector<std::string> T::*>) {
            def = "[";
            for (const std::string& w : defaults.*b) def += (def.size() > 1 ? ", \"" : "\"") + w + "\"";
            def = def.size() > 1 ? "`" + def + "]`" : "[]";
          } else if constexpr (std::is_same_v<B, Choice<T>>) {
            std::vector<std::string_view> words;
            for (const auto& [word, value] : b.options) {
              words.push_back(word);
              if (value == b.get(defaults)) def = "`\"" + word + "\"`";
            }
            allowed = quoted_words(words, "\"", ", ");
          }
        },
        k.binding);
    if (k.range) allowed = k.range->doc();
    if (k.int_range && !std::holds_alternative<Choice<T>>(k.binding)) allowed = k.int_range->doc();
    if (k.int_range && std::holds_alternative<std::array<int, 3> T::*>(k.binding)) allowed = "each " + allowed;
    // A selector lists the keys each of its values reads; a key read by some values says which.
    if (!k.variants.empty()) allowed = variants_doc(k);
    if (selected(k.name) && def != "none") {
      const std::string needed = needed_by(k.name);
      if (!needed.empty()) def = "required (" + needed + ")";
    }
    if (d.default_text.empty()) d.default_text = def;
    if (d.allowed.empty()) d.allowed = allowed;
    out.push_back(std::move(d));
  }
  return out;
}

template <class T>
std::vector<std::string> KeyTable<T>::set_values(const T& t) const {
  const T defaults{};
  const auto three = [](const auto& v, const auto& text) { return "[" + text(v[0]) + ", " + text(v[1]) + ", " + text(v[2]) + "]"; };
  const auto number = [](double v) { return show(v); };
  const auto quoted = [](const std::string& v) { return "\"" + v + "\""; };
  std::vector<std::string> out;
  for (const Key<T>& k : keys_) {
    if (!used(t, k.name)) continue;
    std::string text;
    std::visit(
        [&](const auto& b) {
          using B = std::decay_t<decltype(b)>;
          if constexpr (std::is_same_v<B, Choice<T>>) {
            if (b.get(t) != b.get(defaults))
              for (const auto& [word, value] : b.options)
                if (value == b.get(t)) text = quoted(word);
          } else if constexpr (!std::is_same_v<B, Custom>) {
            const auto& v = t.*b;
            if (v == defaults.*b) return;
            using V = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<V, double>) {
              text = number(v);
            } else if constexpr (std::is_same_v<V, std::optional<double>>) {
              text = v ? number(*v) : "none";
            } else if constexpr (std::is_same_v<V, int> || std::is_same_v<V, std::uint64_t>) {
              text = std::to_string(v);
            } else if constexpr (std::is_same_v<V, bool>) {
              text = v ? "true" : "false";
            } else if constexpr (std::is_same_v<V, std::string>) {
              text = quoted(v);
            } else if constexpr (std::is_same_v<V, std::array<double, 3>>) {
              text = three(v, number);
            } else if constexpr (std::is_same_v<V, std::optional<std::array<double, 3>>>) {
              text = v ? three(*v, number) : "none";
            } else if constexpr (std::is_same_v<V, std::array<int, 3>>) {
              text = three(v, [](int x) { return std::to_string(x); });
            } else if constexpr (std::is_same_v<V, std::array<bool, 3>>) {
              text = three(v, [](bool x) { return std::string(x ? "true" : "false"); });
            } else {
              for (const std::string& w : v) text += (text.empty() ? "" : ", ") + quoted(w);
              text = "[" + text + "]";
            }
          }
        },
        k.binding);
    if (!text.empty()) out.push_back(k.name + " = " + text + (k.unit.empty() ? "" : " " + k.unit));
  }
  return out;
}

// The markdown table of docs/config.md for `rows`.
std::string markdown(const std::vector<KeyDoc>& rows);

// A config table as the schema reads it (src/schema/section.hpp implements this over TOML). Each read()
// leaves `out` alone when the key is absent and throws a ConfigError naming the key (file:line:col)
// when its type is wrong; missing() reports an absent required key.
class Reader {
 public:
  virtual ~Reader() = default;
  virtual bool has(std::string_view key) const = 0;
  virtual void read(std::string_view key, double& out) const = 0;
  virtual void read(std::string_view key, std::optional<double>& out) const = 0;
  virtual void read(std::string_view key, int& out) const = 0;
  virtual void read(std::string_view key, std::uint64_t& out) const = 0;
  virtual void read(std::string_view key, bool& out) const = 0;
  virtual void read(std::string_view key, std::string& out) const = 0;
  virtual void read(std::string_view key, std::array<double, 3>& out) const = 0;
  virtual void read(std::string_view key, std::optional<std::array<double, 3>>& out) const = 0;
  // Whole numbers; a fraction is refused as "not a whole number of <noun>".
  virtual void read(std::string_view key, std::array<int, 3>& out, std::string_view noun) const = 0;
  virtual void read(std::string_view key, std::array<bool, 3>& out) const = 0;
  virtual void read(std::string_view key, std::vector<std::string>& out) const = 0;
  virtual std::optional<int> choice(std::string_view key,
                                    const std::vector<std::pair<std::string, int>>& options) const = 0;
  [[noreturn]] virtual void missing(std::string_view key, std::string_view hint) const = 0;
  // The refusal of a written key ("file:line:col key = value: why").
  [[noreturn]] virtual void refuse(std::string_view key, std::string_view why) const = 0;
  // The key's full name ("solid[1].shape") and its value as written ("\"plane\"").
  virtual std::string full_name(std::string_view key) const = 0;
  virtual std::string written(std::string_view key) const = 0;
};

// `text` with "{key}" and "{value}" replaced.
std::string fill_in(std::string text, std::string_view key, std::string_view value);

// Fills `out` from the keys of `table` that `s` holds. A selector (variant()) is read first and an
// absent required one reported at once; then each key it governs is refused where its value does not
// read it, or reported missing where it must; then the other written keys are read (and their types
// checked) before an absent required one is reported. Custom keys are left to their model's own code.
template <class T>
void read_keys(const KeyTable<T>& table, const Reader& s, T& out) {
  const Key<T>* sel = table.selector();
  if (sel) {
    const Choice<T>& c = std::get<Choice<T>>(sel->binding);
    if (const auto v = s.choice(sel->name, c.options)) c.set(out, *v);
    else if (sel->required) s.missing(sel->name, sel->missing_hint);
    const auto variant = std::find_if(sel->variants.begin(), sel->variants.end(),
                                      [&](const Variant& v) { return v.value == c.get(out); });
    const auto listed = [](const std::vector<std::string>& list, const std::string& name) {
      return std::find(list.begin(), list.end(), name) != list.end();
    };
    const std::string key = s.full_name(sel->name), value = s.has(sel->name) ? s.written(sel->name) : std::string();
    for (const Key<T>& k : table.keys()) {
      if (!table.selected(k.name)) continue;
      const bool needed = variant != sel->variants.end() && listed(variant->required, k.name);
      const bool allowed = needed || (variant != sel->variants.end() && listed(variant->optional, k.name));
      if (s.has(k.name) && !allowed) s.refuse(k.name, keys::fill_in(sel->unused_why, key, value));
      if (!s.has(k.name) && needed) s.missing(k.name, keys::fill_in(sel->needed_hint, key, value));
    }
  }
  for (const Key<T>& k : table.keys()) {
    if (&k == sel) continue;
    std::visit(
        [&](const auto& b) {
          using B = std::decay_t<decltype(b)>;
          if constexpr (std::is_same_v<B, Choice<T>>) {
            if (const auto v = s.choice(k.name, b.options)) b.set(out, *v);
          } else if constexpr (std::is_same_v<B, std::array<int, 3> T::*>) {
            s.read(k.name, out.*b, k.noun);
          } else if constexpr (!std::is_same_v<B, Custom>) {
            s.read(k.name, out.*b);
          }
        },
        k.binding);
  }
  for (const Key<T>& k : table.keys())
    if (k.required && &k != sel && !std::holds_alternative<Custom>(k.binding) && !s.has(k.name))
      s.missing(k.name, k.missing_hint);
}

}  // namespace keys
}  // namespace mesodpd
