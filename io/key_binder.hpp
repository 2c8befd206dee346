#pragma once
// Each case-file key written once: a section of keys is one function
//
//   void bind(io::KeyBinder& keys, Settings& s)
//   {
//     keys.real("viscosity", "blood viscosity", s.mu).unit("cP").defaults(4.0).positive();
//     ...
//   }
//
// run twice: against a Schema (KeyBinder(schema)) it declares the keys, with their documentation, unit,
// default and range; against the validated Config (KeyBinder(config)) it reads each key into its target,
// in CGS. The key's name, its checks and where its value goes are then in one line, and the schema
// cannot drift from what the code reads. A binder may carry a prefix ("windkessel"): its keys are then
// "windkessel.<key>", so one section serves several tables.
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/config.hpp"

namespace ibvalve::io {

class KeyBinder {
 public:
  /// Declares keys into `schema`.
  explicit KeyBinder(Schema& schema, std::string prefix = "");
  /// Reads keys from `config` (validated against a schema the same binds declared).
  explicit KeyBinder(const Config& config, std::string prefix = "");

  /// True when reading a Config; false when declaring a Schema.
  bool reading() const { return config_ != nullptr; }
  /// The Config being read (reading() only): for the checks a schema cannot express, config().fail(...).
  const Config& config() const;
  /// The full key of `key`: "<prefix>.<key>", or `key` without a prefix.
  std::string full(std::string_view key) const;
  /// Declaring: refuses `key` with "file:line: key: <why>" (Schema::retire); reading: nothing.
  void retired(std::string_view key, std::string why);

  KeyBuilder boolean(std::string_view key, std::string doc, bool& target);
  KeyBuilder real(std::string_view key, std::string doc, double& target);
  /// An optional key without a default: the target is set only when the case gives it.
  KeyBuilder real(std::string_view key, std::string doc, std::optional<double>& target);
  KeyBuilder string(std::string_view key, std::string doc, std::string& target);
  /// A file named relative to the case file's folder (KeyBuilder::file); unset leaves the target empty.
  KeyBuilder path(std::string_view key, std::string doc, std::filesystem::path& target,
                  bool must_exist = true);
  /// A list of files, each named relative to the case file's folder and required to exist; unset leaves
  /// the target empty.
  KeyBuilder paths(std::string_view key, std::string doc, std::vector<std::filesystem::path>& target);
  KeyBuilder reals(std::string_view key, std::string doc, std::vector<double>& target);
  KeyBuilder integers(std::string_view key, std::string doc, std::vector<std::int64_t>& target);
  KeyBuilder strings(std::string_view key, std::string doc, std::vector<std::string>& target);
  /// A table of numbers under names the user chooses (`key = { a = 1.0, b = 2.5 }`), as written (no
  /// unit conversion); unset leaves the target empty.
  KeyBuilder named_reals(std::string_view key, std::string doc,
                         std::vector<std::pair<std::string, double>>& target);
  /// An array of tables ([[key]]), each element's keys bound by `bind_element(KeyBinder&, T&)`: declaring,
  /// they make the element's schema; reading, the target holds one T per element given, in order, each
  /// read by a binder of the element's own whose keys this binder then knows (key_of names the key within
  /// the element, fail names the element: "structure.part[1].group"). Unset leaves the target empty. The
  /// elements are bound where they lie: the target must not grow or shrink afterwards.
  template <class T, class BindElement>
  KeyBuilder tables(std::string_view key, std::string doc, std::vector<T>& target, BindElement bind_element)
  {
    bound(key, &target);
    if (!reading()) {
      Schema element;
      KeyBinder declaring(element);
      T unused{};
      bind_element(declaring, unused);
      return schema_->add_table_list(full(key), std::move(element), std::move(doc));
    }
    target.clear();
    if (config_->has(full(key))) {
      const std::vector<Config> elements = config_->tables(full(key));
      target.resize(elements.size());
      for (std::size_t i = 0; i < elements.size(); ++i) {
        auto element = std::make_shared<const Config>(elements[i]);
        KeyBinder reading(*element);
        bind_element(reading, target[i]);
        adopt(std::move(reading), std::move(element));
      }
    }
    return scratch();
  }

  /// The key bound to `target` (a field this binder bound), for messages about it.
  template <class T>
  const std::string& key_of(const T& target) const
  {
    return key_at(std::addressof(target));
  }
  /// Throws the InputError "file:line: key: message" of the key bound to `target` (reading only), for
  /// the checks a schema cannot express.
  template <class T>
  [[noreturn]] void fail(const T& target, std::string_view message) const
  {
    const Bound& b = bound_at(std::addressof(target));
    holder(b).fail(b.key, message);
  }
  /// Whether the key bound to `target` has a value (reading only): the case gives it, or it has a
  /// default. A key without a default that the case leaves out has none, and its target is as it was.
  template <class T>
  bool has(const T& target) const
  {
    const Bound& b = bound_at(std::addressof(target));
    return holder(b).has(b.key);
  }
  /// The Config that holds the key bound to `target` (reading only): this binder's, or for a key of a
  /// table list's element the element's; for messages about parts of a key (a named number of a table).
  template <class T>
  const Config& config_of(const T& target) const
  {
    return holder(bound_at(std::addressof(target)));
  }
  /// A temporary is no bound field (a key_of(...) result, say): refused at compile time, not at run time.
  template <class T>
  const std::string& key_of(const T&& target) const = delete;
  template <class T>
  void fail(const T&& target, std::string_view message) const = delete;
  template <class T>
  bool has(const T&& target) const = delete;
  template <class T>
  const Config& config_of(const T&& target) const = delete;

  template <std::integral T>
  KeyBuilder integer(std::string_view key, std::string doc, T& target)
  {
    bound(key, &target);
    if (reading()) {
      if (config_->has(full(key))) target = static_cast<T>(config_->integer(full(key)));
      return scratch();
    }
    return schema_->add_integer(full(key), std::move(doc));
  }

  /// A string key naming one of `names` (declared as its choices), read into the matching value.
  template <class E>
  KeyBuilder choice(std::string_view key, std::string doc, E& target,
                    const std::vector<std::pair<std::string, E>>& names)
  {
    bound(key, &target);
    if (reading()) {
      if (config_->has(full(key))) {
        const std::string name = config_->string(full(key));
        for (const auto& [text, value] : names)
          if (text == name) target = value;
      }
      return scratch();
    }
    std::vector<std::string> allowed;
    for (const auto& entry : names) allowed.push_back(entry.first);
    KeyBuilder builder = schema_->add_string(full(key), std::move(doc));
    builder.choices(std::move(allowed));
    return builder;
  }

 private:
  /// A bound target, its full key and the Config that holds the key (null while declaring).
  struct Bound {
    const void* target;
    std::string key;
    const Config* config;
  };

  /// What a reading binder returns: a builder whose settings go nowhere.
  KeyBuilder scratch();
  void bound(std::string_view key, const void* target);
  const Bound& bound_at(const void* target) const;
  const std::string& key_at(const void* target) const { return bound_at(target).key; }
  /// The Config holding a bound key (reading only).
  const Config& holder(const Bound& bound) const;
  /// Takes over what a table element's binder bound (and the elements it read), with the element's Config.
  void adopt(KeyBinder&& element_binder, std::shared_ptr<const Config> element);

  Schema* schema_ = nullptr;
  const Config* config_ = nullptr;
  std::string prefix_;
  KeySpec scratch_;
  std::vector<Bound> bound_;                            // each target, its full key and its Config
  std::vector<std::shared_ptr<const Config>> elements_; // the table elements read, which bound_ points into
};

} // namespace ibvalve::io
