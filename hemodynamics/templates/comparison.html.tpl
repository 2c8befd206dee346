{{! The HTML page of `ibvalve compare` (Mustache: https://mustache.github.io/mustache.5.html).
    A name in double braces is HTML-escaped, one in triple braces inserted as it is. The names are
    those of comparison.md.tpl:
      count, cases (name), has_differences, differences (key, values (value)), metrics (key, symbol,
      label, unit, synthetic, values (value, exact, missing)), left_out_note, criterion_notes (text),
      criteria (key, label, higher_is_better), ranking (in rank order: name, scores (value, missing),
      total, rank, rank_held), uncertain, uncertainty_note, plots (file, caption, png_base64: embedded,
      so the page opens anywhere).
    docs/hemodynamics.md says how to use your own copy (ibvalve compare --templates). }}
<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>ibvalve comparison</title>
<style>
body{font-family:sans-serif;margin:2em}table{border-collapse:collapse;margin:1em 0}
td,th{border:1px solid #bbb;padding:3px 8px}td.value{text-align:right;font-variant-numeric:tabular-nums}
.missing{color:#999}.note{border-left:4px solid #b26a00;background:#fff8e1;padding:0.3em 0.8em}
</style>
</head>
<body>
<h1>ibvalve comparison of {{count}} case(s)</h1>
<h2>What differs between the cases</h2>
{{#has_differences}}
<table id="differences">
<tr><th>input</th>{{#cases}}<th>{{name}}</th>{{/cases}}</tr>
{{#differences}}
<tr data-input="{{key}}"><td><code>{{key}}</code></td>{{#values}}<td>{{value}}</td>{{/values}}</tr>
{{/differences}}
</table>
{{/has_differences}}
{{^has_differences}}
<p>Their recorded inputs (config.toml) are the same, but for their names.</p>
{{/has_differences}}
<h2>Metrics per case (Table 7 style)</h2>
<table id="metrics">
<tr><th>metric</th><th>unit</th>{{#cases}}<th>{{name}}</th>{{/cases}}</tr>
{{#metrics}}
<tr data-key="{{key}}"><td>{{symbol}} (<code>{{key}}</code>){{#synthetic}} (synthetic data: see the note under the ranking){{/synthetic}}</td><td>{{unit}}</td>{{#values}}<td class="value{{#missing}} missing{{/missing}}" data-value="{{exact}}">{{value}}</td>{{/values}}</tr>
{{/metrics}}
</table>
<h2>Ranking (Table 8 style), best first</h2>
<p>Each criterion: best case 1, worst 0, linear in between; total = sum; rank by total. {{left_out_note}}. {{uncertainty_note}}.</p>
{{#criterion_notes}}
<p class="note"><strong>Note:</strong> {{text}}.</p>
{{/criterion_notes}}
<table id="ranking">
<tr><th>case</th>{{#criteria}}<th>{{label}} {{#higher_is_better}}&uarr;{{/higher_is_better}}{{^higher_is_better}}&darr;{{/higher_is_better}}</th>{{/criteria}}<th>total</th><th>rank</th>{{#uncertain}}<th>rank held</th>{{/uncertain}}</tr>
{{#ranking}}
<tr><td>{{name}}</td>{{#scores}}<td class="value{{#missing}} missing{{/missing}}">{{value}}</td>{{/scores}}<td class="value">{{total}}</td><td class="value">{{rank}}</td>{{#uncertain}}<td class="value">{{rank_held}}</td>{{/uncertain}}</tr>
{{/ranking}}
</table>
<h2>Curves</h2>
{{#plots}}
<figure><a href="{{file}}"><img alt="{{caption}}" src="data:image/png;base64,{{{png_base64}}}"></a><figcaption>{{caption}} (<a href="{{file}}">{{file}}</a>)</figcaption></figure>
{{/plots}}
{{^plots}}
<p>(no plots)</p>
{{/plots}}
</body>
</html>
