// `ibvalve keys [MODEL]`: every case-file key with its type, unit, default, range and meaning, as
// Markdown tables or as a TOML case skeleton, from the same schema `ibvalve run` validates against.
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "app/commands.hpp"
#include "app/model.hpp"
#include "base/errors.hpp"
#include "io/collective.hpp"

namespace ibvalve::app {

namespace {

struct KeysOptions {
  std::string model;
  std::string format = "markdown";
};

std::string model_list()
{
  std::string list;
  for (const Model& m : models()) list += (list.empty() ? "" : ", ") + m.name;
  return list;
}

/// The keys `model` adds to the common ones.
io::Schema own_keys(const Model& model)
{
  io::Schema own;
  model.add_schema(own);
  return own;
}

std::string markdown(const Model* only)
{
  std::ostringstream os;
  os << "# Case-file keys" << (only ? " of the " + only->name + " model" : "") << "\n\n"
     << "Units are those a case file writes; `ibvalve run` converts them to CGS. Overrides: "
        "`ibvalve run CASE --set key=value`.\n\n"
     << "## Every model\n\n"
     << common_schema().markdown();
  for (const Model& m : models()) {
    if (only && &m != only) continue;
    os << "\n## Model `" << m.name << "`\n\n" << m.description << "\n\n" << own_keys(m).markdown();
  }
  return os.str();
}

int print_keys(const KeysOptions& options)
{
  const Model* model = nullptr;
  if (!options.model.empty()) {
    model = find_model(options.model);
    if (!model)
      throw InputError("command line: keys " + options.model + ": no such model (models: " + model_list() +
                       ")");
  }
  if (options.format == "toml" && !model)
    throw InputError(
        "command line: keys --format toml: give a model (a case is of one model: " + model_list() + ")");
  std::string text;
  if (options.format == "toml") {
    const bool vowel = std::string_view("aeiou").find(model->name.front()) != std::string_view::npos;
    std::string head = std::string(vowel ? "# An " : "# A ") + model->name +
                       " case, every key at its default (ibvalve keys " + model->name +
                       " --format toml).\n# " + model->description +
                       "\n# REQUIRED keys hold an example value; commented keys are optional.\n";
    const std::vector<std::pair<std::string, io::Value>> fixed{{"model", model->name}};
    text = case_schema(*model).toml_skeleton(head, fixed);
  } else {
    text = markdown(model);
  }
  io::on_root(MPI_COMM_WORLD, [&] { std::cout << text << std::flush; });
  return 0;
}

} // namespace

void add_keys_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<KeysOptions>();
  CLI::App* sub = app.add_subcommand(
      "keys", "List every case-file key (type, unit, default, range, meaning) of every model or of MODEL");
  sub->add_option("model", options->model, "one model: " + model_list());
  sub->add_option("--format", options->format,
                  "markdown (a table per model) or toml (a case skeleton of MODEL, every key at its default)")
      ->check(CLI::IsMember({"markdown", "toml"}));
  sub->callback(
      [options, &action] { action = [options](const PetscArguments&) { return print_keys(*options); }; });
}

} // namespace ibvalve::app
