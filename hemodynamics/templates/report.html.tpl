{{! The HTML report of `ibvalve report` (Mustache: https://mustache.github.io/mustache.5.html).
    A name in double braces is HTML-escaped, one in triple braces inserted as it is. The names are
    those of report.md.tpl:
      run, cycle, cycles, cycle_start, cycle_end, headline (key, name, symbol, value, missing, unit,
      range, source, assessment, outside), checks (check, text), has_warnings, warnings (text),
      references (name, citation),
      has_cycle_table, cycle_rows (cycle, page, reported, vf, tpg, pwk_start, pwk_end, pwk_change),
      periodicity, groups (group, metrics), metrics (key, label, description, symbol, value, exact,
      missing, unit, note, uncertainty, uncertainty_sources), phases (name, time), ejection_windows
      (condition, start, chosen, tpg, qrms, eoa), plots (file, caption, png_base64), notes (text),
      provenance (name, value), inputs (key, value: shortest exact numbers with their unit).
    The plots are embedded (the file opens anywhere) and linked to the PNGs beside it.
    docs/hemodynamics.md says how to use your own copy (report.templates). }}
<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>ibvalve report: {{run}}, cycle {{cycle}} of {{cycles}}</title>
<style>
body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;text-align:left}
td.value{text-align:right;font-variant-numeric:tabular-nums}figure{margin:1.5em 0}img{max-width:100%}
.missing{color:#999}tr.outside td{background:#fff3cd}
.implausible{border:2px solid #b00020;background:#fdecea;padding:0.5em 1em;margin:1em 0}
.warnings{border:2px solid #b26a00;background:#fff8e1;padding:0.5em 1em;margin:1em 0}
</style>
</head>
<body>
<h1>ibvalve report: {{run}}, cycle {{cycle}} of {{cycles}}</h1>
<p>Cycle {{cycle}} of {{cycles}}: [{{cycle_start}}, {{cycle_end}}] s of <code>timeseries.csv</code>. Definitions and phase rules: docs/hemodynamics.md.</p>
<h2>At a glance</h2>
{{#checks}}
<p class="implausible" data-check="{{check}}"><strong>Implausible:</strong> {{text}}</p>
{{/checks}}
{{#has_warnings}}
<div class="warnings" id="warnings"><strong>The run's warnings</strong> (log.txt, run.json; <code>ibvalve run --strict</code> makes them errors):
<ul>
{{#warnings}}
<li>{{text}}</li>
{{/warnings}}
</ul></div>
{{/has_warnings}}
<table id="headline">
<tr><th>figure</th><th>symbol</th><th>value</th><th>unit</th><th>healthy adult native valve</th><th>source</th><th></th></tr>
{{#headline}}
<tr data-headline="{{key}}"{{#outside}} class="outside"{{/outside}}><td>{{name}}</td><td>{{symbol}}</td><td class="value{{#missing}} missing{{/missing}}">{{value}}</td><td>{{unit}}</td><td>{{range}}</td><td>{{source}}</td><td>{{#outside}}outside{{/outside}}</td></tr>
{{/headline}}
</table>
<p>The ranges are the published bounds of the mildest grade of disease (sources below): a healthy valve lies on their near side. A figure without a range has no published one here. The peak velocity is the jet's: the largest fluid speed in the tube between the pressure probes, off the box's sides (the run's log names the region; docs/hemodynamics.md, "Peak velocity").</p>
{{#has_cycle_table}}
<h2>Cycle to cycle</h2>
<p>{{periodicity}}.</p>
<table id="cycles">
<tr><th>cycle</th><th>V_F (mL)</th><th>TPG (mmHg)</th><th>P_Wk start (mmHg)</th><th>P_Wk end (mmHg)</th><th>P_Wk change (mmHg)</th></tr>
{{#cycle_rows}}
<tr><td><a href="{{page}}">{{cycle}}</a>{{#reported}} (this report){{/reported}}</td><td class="value">{{vf}}</td><td class="value">{{tpg}}</td><td class="value">{{pwk_start}}</td><td class="value">{{pwk_end}}</td><td class="value">{{pwk_change}}</td></tr>
{{/cycle_rows}}
</table>
{{/has_cycle_table}}
<h2>Plots</h2>
{{#plots}}
<figure><a href="{{file}}"><img alt="{{caption}}" src="data:image/png;base64,{{{png_base64}}}"></a><figcaption>{{caption}} (<a href="{{file}}">{{file}}</a>)</figcaption></figure>
{{/plots}}
{{^plots}}
<p>(no plots)</p>
{{/plots}}
<h2>Metrics</h2>
{{#groups}}
<h3>{{group}}</h3>
<table class="metrics">
<tr><th>metric</th><th>symbol</th><th>value</th><th>unit</th><th>note</th></tr>
{{#metrics}}
<tr data-key="{{key}}"><td>{{description}} (<code>{{key}}</code>)</td><td>{{symbol}}</td><td class="value{{#missing}} missing{{/missing}}" data-value="{{exact}}">{{value}}{{#uncertainty}} {{uncertainty}}{{/uncertainty}}</td><td>{{unit}}</td><td>{{note}}{{#uncertainty_sources}} (u from {{uncertainty_sources}}){{/uncertainty_sources}}</td></tr>
{{/metrics}}
</table>
{{/groups}}
<h2>Phases</h2>
<table id="phases">
<tr><th>instant</th><th>time (s)</th></tr>
{{#phases}}
<tr><td>{{name}}</td><td class="value">{{time}}</td></tr>
{{/phases}}
</table>
<h2>Ejection window</h2>
<p>TPG, Q_rms and EOA are means over ejection, from t_bs, the latest of the conditions below (the valve open and the flow forward), to the end of forward flow t_es. On the window each condition alone would open they are:</p>
<table id="ejection_windows">
<tr><th>t_bs from</th><th>start (s)</th><th>TPG (mmHg)</th><th>Q_rms (mL/s)</th><th>EOA (cm^2)</th><th></th></tr>
{{#ejection_windows}}
<tr><td>{{condition}}</td><td class="value">{{start}}</td><td class="value">{{tpg}}</td><td class="value">{{qrms}}</td><td class="value">{{eoa}}</td><td>{{#chosen}}used{{/chosen}}</td></tr>
{{/ejection_windows}}
</table>
<h2>Notes</h2>
<ul>
{{#notes}}
<li>{{text}}</li>
{{/notes}}
<li>E_L sign: dp = P_LV - P_Ao, so energy dissipated across the valve is positive.</li>
</ul>
<h2>Sources of the ranges</h2>
<ul id="references">
{{#references}}
<li><strong>{{name}}</strong>: {{citation}}</li>
{{/references}}
</ul>
<h2>Inputs and provenance</h2>
<table id="provenance">
{{#provenance}}
<tr><th>{{name}}</th><td>{{value}}</td></tr>
{{/provenance}}
</table>
<details><summary>Every input of the case (config.toml)</summary>
<table id="inputs">
<tr><th>key</th><th>value</th></tr>
{{#inputs}}
<tr><td><code>{{key}}</code></td><td>{{value}}</td></tr>
{{/inputs}}
</table>
</details>
</body>
</html>
