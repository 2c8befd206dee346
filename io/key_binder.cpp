#include "io/key_binder.hpp"

#include <stdexcept>

namespace ibvalve::io {

KeyBinder::KeyBinder(Schema& schema, std::string prefix) : schema_(&schema), prefix_(std::move(prefix)) {}

KeyBinder::KeyBinder(const Config& config, std::string prefix) : config_(&config), prefix_(std::move(prefix))
{
}

const Config& KeyBinder::config() const
{
  if (!config_) throw std::logic_error("KeyBinder::config() while declaring a schema");
  return *config_;
}

std::string KeyBinder::full(std::string_view key) const
{
  return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key);
}

void KeyBinder::retired(std::string_view key, std::string why)
{
  if (!reading()) schema_->retire(full(key), std::move(why));
}

void KeyBinder::bound(std::string_view key, const void* target)
{
  bound_.push_back({target, full(key), config_});
}

const KeyBinder::Bound& KeyBinder::bound_at(const void* target) const
{
  for (const Bound& b : bound_)
    if (b.target == target) return b;
  throw std::logic_error("KeyBinder: no key is bound to this target");
}

const Config& KeyBinder::holder(const Bound& bound) const
{
  if (!bound.config) throw std::logic_error("KeyBinder: a key's Config while declaring a schema");
  return *bound.config;
}

void KeyBinder::adopt(KeyBinder&& element_binder, std::shared_ptr<const Config> element)
{
  for (Bound& b : element_binder.bound_) bound_.push_back(std::move(b));
  for (auto& kept : element_binder.elements_) elements_.push_back(std::move(kept));
  elements_.push_back(std::move(element));
}

KeyBuilder KeyBinder::scratch()
{
  scratch_ = KeySpec{};
  return KeyBuilder(scratch_);
}

KeyBuilder KeyBinder::boolean(std::string_view key, std::string doc, bool& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->boolean(full(key));
    return scratch();
  }
  return schema_->add_boolean(full(key), std::move(doc));
}

KeyBuilder KeyBinder::real(std::string_view key, std::string doc, double& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->real(full(key));
    return scratch();
  }
  return schema_->add_real(full(key), std::move(doc));
}

KeyBuilder KeyBinder::real(std::string_view key, std::string doc, std::optional<double>& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->real(full(key));
    return scratch();
  }
  return schema_->add_real(full(key), std::move(doc));
}

KeyBuilder KeyBinder::string(std::string_view key, std::string doc, std::string& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->string(full(key));
    return scratch();
  }
  return schema_->add_string(full(key), std::move(doc));
}

KeyBuilder KeyBinder::path(std::string_view key, std::string doc, std::filesystem::path& target,
                           bool must_exist)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->path(full(key));
    return scratch();
  }
  KeyBuilder builder = schema_->add_string(full(key), std::move(doc));
  builder.file(must_exist);
  return builder;
}

KeyBuilder KeyBinder::paths(std::string_view key, std::string doc, std::vector<std::filesystem::path>& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->paths(full(key));
    return scratch();
  }
  KeyBuilder builder = schema_->add_string_list(full(key), std::move(doc));
  builder.file(true);
  return builder;
}

KeyBuilder KeyBinder::reals(std::string_view key, std::string doc, std::vector<double>& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->reals(full(key));
    return scratch();
  }
  return schema_->add_real_list(full(key), std::move(doc));
}

KeyBuilder KeyBinder::integers(std::string_view key, std::string doc, std::vector<std::int64_t>& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->integers(full(key));
    return scratch();
  }
  return schema_->add_integer_list(full(key), std::move(doc));
}

KeyBuilder KeyBinder::strings(std::string_view key, std::string doc, std::vector<std::string>& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->strings(full(key));
    return scratch();
  }
  return schema_->add_string_list(full(key), std::move(doc));
}

KeyBuilder KeyBinder::named_reals(std::string_view key, std::string doc,
                                  std::vector<std::pair<std::string, double>>& target)
{
  bound(key, &target);
  if (reading()) {
    if (config_->has(full(key))) target = config_->named_reals(full(key));
    return scratch();
  }
  return schema_->add_real_table(full(key), std::move(doc));
}

} // namespace ibvalve::io
