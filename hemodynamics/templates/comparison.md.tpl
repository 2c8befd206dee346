{{! The Markdown page of `ibvalve compare` (Mustache: https://mustache.github.io/mustache.5.html).
    Values are inserted with <, >, & as HTML entities and | as \| (a name from a user's files cannot
    open a tag or end a table cell; a tag in triple braces inserts a value as it is). What a template
    can use:
      count                     the number of cases
      cases                     list: name
      metrics                   list, one per metric of any case: key, symbol, label ("symbol (`key`)",
                                or the key when there is no symbol), unit, synthetic (true when some
                                case's figure is measured against synthetic data), values (list, one
                                per case:
                                value (4 significant digits, "± u" after it when the metric carries
                                an uncertainty, or "missing"), exact (every digit, or
                                "null"), missing (true when the case has no value))
      has_differences           true when the cases' inputs differ in some key
      differences               list, the inputs that differ between the cases (their config.toml keys
                                but name and the output, log, run and checkpoint tables): key, values
                                (list, one per case: value, "(unset)" where a case lacks the key)
      left_out_note             how many of the 12 criteria are ranked, and which are left out and why
      criterion_notes           list, what a criterion's figures rest on (the fit error measured against
                                synthetic samples): text
      criteria                  list, the study's 12: key, label, higher_is_better
      ranking                   list, one per case, in rank order: name, scores (list, one per ranked
                                criterion: value,
                                missing), total, rank, rank_held ("87 %": how often the case keeps its
                                rank when the uncertain metrics are drawn about their values)
      uncertain                 true when some ranked metric carries an uncertainty
      uncertainty_note          how uncertainties enter the scores and how stable the order is
      plots                     list, the overlaid curves drawn: file (PNG beside the page), caption,
                                png_base64
    docs/hemodynamics.md says how to use your own copy (ibvalve compare --templates). }}
# ibvalve comparison of {{count}} case(s)

## What differs between the cases

{{#has_differences}}
| input |{{#cases}} {{name}} |{{/cases}}
|---|{{#cases}}---|{{/cases}}
{{#differences}}
| `{{key}}` |{{#values}} {{value}} |{{/values}}
{{/differences}}
{{/has_differences}}
{{^has_differences}}
Their recorded inputs (config.toml) are the same, but for their names.
{{/has_differences}}

## Metrics per case (Table 7 style)

| metric | unit |{{#cases}} {{name}} |{{/cases}}
|---|---|{{#cases}}---|{{/cases}}
{{#metrics}}
| {{label}}{{#synthetic}} (synthetic data: see the note under the ranking){{/synthetic}} | {{unit}} |{{#values}} {{value}} |{{/values}}
{{/metrics}}

## Ranking (Table 8 style), best first

Each criterion: best case 1, worst 0, linear in between; total = sum; rank by total. {{left_out_note}}.
{{uncertainty_note}}.
{{#criterion_notes}}

> **Note:** {{text}}.
{{/criterion_notes}}

| case |{{#criteria}} {{label}} ({{#higher_is_better}}higher{{/higher_is_better}}{{^higher_is_better}}lower{{/higher_is_better}} better) |{{/criteria}} total | rank |{{#uncertain}} rank held |{{/uncertain}}
|---|{{#criteria}}---|{{/criteria}}---|---|{{#uncertain}}---|{{/uncertain}}
{{#ranking}}
| {{name}} |{{#scores}} {{value}} |{{/scores}} {{total}} | {{rank}} |{{#uncertain}} {{rank_held}} |{{/uncertain}}
{{/ranking}}

## Curves

{{#plots}}
![{{caption}}]({{file}})

{{/plots}}
{{^plots}}
(no plots)
{{/plots}}
