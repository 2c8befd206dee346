{{! The Markdown report of `ibvalve report` (Mustache: https://mustache.github.io/mustache.5.html).
    Values are inserted with <, >, & as HTML entities and | as \| (a name from a user's files cannot
    open a tag or end a table cell; a tag in triple braces inserts a value as it is). What a template
    can use:
      run                       the run folder's name (or its config's `name`)
      cycle, cycles             the analysed cycle (counted from 1) and the whole cycles of the series
      cycle_start, cycle_end    the analysed cycle, s, 4 significant digits
      headline                  list, the figures a reader looks at first: key, name, symbol, value (4
                                significant digits, or "missing"), missing, unit, range (a healthy adult
                                native valve's published range, or empty), source (its short citation),
                                assessment ("within", "outside" or empty), outside (true when outside)
      checks                    list, the figures no valve can have: check (eoa_above_goa,
                                not_periodic), text
      has_warnings, warnings    whether the run gave warnings; list: text (each as log.txt has it,
                                kept in its run.json)
      references                list: name (the short citation), citation (the full one)
      has_cycle_table           true when the series holds two cycles or more up to this one
      cycle_rows                list, cycles 1 to this one: cycle, page (that cycle's report.html),
                                reported (true for this one), vf (mL), tpg (mmHg), pwk_start, pwk_end,
                                pwk_change (mmHg, P_Wk's change over the cycle)
      periodicity               one sentence: this cycle against the one before, and P_Wk's change
      groups                    list: group ("flow and pressure", "valve motion", "leaflet mechanics",
                                "other"), metrics (as below, the group's)
      metrics                   list, every metric: key, label (description, else key), description,
                                symbol, value (4 significant digits, or "missing"), exact (every digit,
                                or "null"), missing (true when there is no value), unit, note,
                                uncertainty ("± 0.91", the standard uncertainty from the run's
                                uncertainty.json, or empty), uncertainty_sources ("time step 0.91")
      phases                    list: name, time (s, 4 significant digits, "missing", or a rule's name)
      ejection_windows          list: condition, start (s), chosen (true for the window the metrics
                                use), tpg (mmHg), qrms (mL/s), eoa (cm^2): the means over ejection on
                                the window each condition alone would open
      plots                     list: file (PNG beside the report), caption, png_base64
      notes                     list: text
      provenance                list: name, value (case file, the build that ran it, start, ranks,
                                restarts, the build and time of this report)
      inputs                    list: key, value (the case's keys as config.toml records them, numbers
                                in their shortest exact form, with their unit: "3e-05 s")
    docs/hemodynamics.md says how to use your own copy (report.templates). }}
# ibvalve report: {{run}}, cycle {{cycle}} of {{cycles}}

Cycle {{cycle}} of {{cycles}}: [{{cycle_start}}, {{cycle_end}}] s of `timeseries.csv`.

## At a glance

{{#checks}}
> **Implausible:** {{text}}

{{/checks}}
{{#has_warnings}}
> **The run's warnings** (log.txt, run.json; `ibvalve run --strict` makes them errors):
{{#warnings}}
> - {{text}}
{{/warnings}}

{{/has_warnings}}
| figure | symbol | value | unit | healthy adult native valve | source | |
|---|---|---|---|---|---|---|
{{#headline}}
| {{name}} (`{{key}}`) | {{symbol}} | {{value}} | {{unit}} | {{range}} | {{source}} | {{#outside}}**outside**{{/outside}} |
{{/headline}}

The ranges are the published bounds of the mildest grade of disease (sources below): a healthy valve
lies on their near side. A figure without a range has no published one here. The peak velocity is the
jet's: the largest fluid speed in the tube between the pressure probes, off the box's sides (the run's
log names the region; docs/hemodynamics.md, "Peak velocity").

{{#has_cycle_table}}
## Cycle to cycle

{{periodicity}}.

| cycle | V_F (mL) | TPG (mmHg) | P_Wk start (mmHg) | P_Wk end (mmHg) | P_Wk change (mmHg) |
|---|---|---|---|---|---|
{{#cycle_rows}}
| [{{cycle}}]({{page}}){{#reported}} (this report){{/reported}} | {{vf}} | {{tpg}} | {{pwk_start}} | {{pwk_end}} | {{pwk_change}} |
{{/cycle_rows}}

{{/has_cycle_table}}
## Plots

{{#plots}}
![{{caption}}]({{file}})

{{/plots}}
{{^plots}}
(no plots)

{{/plots}}
## Metrics

{{#groups}}
### {{group}}

| metric | symbol | value | unit | note |
|---|---|---|---|---|
{{#metrics}}
| {{label}} (`{{key}}`) | {{symbol}} | {{value}}{{#uncertainty}} {{uncertainty}}{{/uncertainty}} | {{unit}} | {{note}}{{#uncertainty_sources}} (u from {{uncertainty_sources}}){{/uncertainty_sources}} |
{{/metrics}}

{{/groups}}
## Phases (s)

| instant | time |
|---|---|
{{#phases}}
| {{name}} | {{time}} |
{{/phases}}

## Ejection window

TPG, Q_rms and EOA are means over ejection, from t_bs, the latest of the conditions below (the valve
open and the flow forward), to the end of forward flow t_es. On the window each condition alone
would open they are:

| t_bs from | start (s) | TPG (mmHg) | Q_rms (mL/s) | EOA (cm^2) | |
|---|---|---|---|---|---|
{{#ejection_windows}}
| {{condition}} | {{start}} | {{tpg}} | {{qrms}} | {{eoa}} | {{#chosen}}used{{/chosen}} |
{{/ejection_windows}}

## Notes

{{#notes}}
- {{text}}
{{/notes}}

## Sources of the ranges

{{#references}}
- {{name}}: {{citation}}
{{/references}}

## Inputs and provenance

| record | |
|---|---|
{{#provenance}}
| {{name}} | {{value}} |
{{/provenance}}

| key | value |
|---|---|
{{#inputs}}
| `{{key}}` | {{value}} |
{{/inputs}}

Definitions: docs/hemodynamics.md. E_L sign: dp = P_LV - P_Ao, so energy dissipated is positive.
