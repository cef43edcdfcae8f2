//! `claims.html`: every claim with its paper, statement, set-up, rule, our numbers, the verdict,
//! its sensitivity (one row per set-up) and its figures, readable offline beside the report's
//! `index.html`.

use super::claims::{Claim, SetupResult, Verdict};
use crate::escape::escape_html as escape;

fn colour(v: Verdict) -> &'static str {
    match v {
        Verdict::Holds => "#009E73",
        // Okabe–Ito sky blue: holds, but within the noise of the set-ups the paper leaves open.
        Verdict::Fragile => "#56B4E9",
        Verdict::Partly => "#E69F00",
        Verdict::DoesNotHold => "#D55E00",
    }
}

fn badge(v: Verdict) -> String {
    format!("<span class=\"verdict\" style=\"background:{}\">{}</span>", colour(v), v.name())
}

const HEAD: &str = "<!doctype html><html><head><meta charset=\"utf-8\"><title>shadowtruth: the papers' claims</title>\
    <style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}\
    .claim{border:1px solid #ccc;border-radius:6px;padding:1em;margin:1em 0}\
    .verdict{color:#fff;padding:.2em .6em;border-radius:4px;font-weight:bold}\
    table{border-collapse:collapse}td,th{border-bottom:1px solid #ddd;padding:.3em .6em;text-align:left}\
    pre{background:#f6f6f6;padding:.6em;overflow:auto}img{max-width:100%}</style></head><body>\
    <h1>The papers' claims, measured</h1><p>Each verdict is computed from the measured numbers by the rule \
    shown, on the set-up that follows the paper; the same rule over other set-ups the paper leaves open is the \
    claim's sensitivity. The margin is the test nearest to changing the verdict on the paper's set-up; a claim \
    that holds by less than that test moves across the other set-ups is <i>fragile</i>. The runs of the papers' set-ups are in <a href=\"index.html\">the report</a>.</p>";

fn summary_table(claims: &[Claim]) -> String {
    let mut h =
        String::from("<table><tr><th>claim</th><th>verdict</th><th>margin</th><th>sensitivity</th></tr>");
    for c in claims {
        h.push_str(&format!(
            "<tr><td><a href=\"#{id}\">{id}</a></td><td>{}</td><td>{}</td><td>{}</td></tr>",
            badge(c.verdict),
            escape(&c.margin),
            escape(&c.sensitivity_summary),
            id = escape(&c.id)
        ));
    }
    h + "</table>"
}

fn sensitivity_table(setups: &[SetupResult]) -> String {
    let mut h = String::from("<table><tr><th>set-up</th><th>verdict</th><th>tests</th><th>numbers</th></tr>");
    for s in setups {
        let numbers = serde_json::to_string(&s.numbers).unwrap_or_default();
        let tests: Vec<String> = s.tests.iter().map(|t| escape(&t.describe())).collect();
        h.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td><details><summary>numbers</summary><pre>{}</pre></details></td></tr>",
            escape(&s.setup),
            badge(s.verdict),
            tests.join("<br>"),
            escape(&numbers)
        ));
    }
    h + "</table>"
}

fn claim_section(c: &Claim) -> String {
    let numbers = serde_json::to_string_pretty(&c.numbers).unwrap_or_default();
    let mut h = format!(
        "<div class=\"claim\" id=\"{id}\"><h2>{id} {badge}</h2><p><i>{paper}</i></p><p>{statement}</p>\
         <p><b>Set-up:</b> {setup}</p><p><b>Rule:</b> {rule}</p><p><b>Margin:</b> {margin}</p><pre>{numbers}</pre>\
         <h3>Sensitivity: {summary}</h3>{table}",
        id = escape(&c.id),
        badge = badge(c.verdict),
        paper = escape(&c.paper),
        statement = escape(&c.statement),
        setup = escape(&c.setup),
        rule = escape(&c.rule),
        margin = escape(&c.margin),
        numbers = escape(&numbers),
        summary = escape(&c.sensitivity_summary),
        table = sensitivity_table(&c.sensitivity),
    );
    for f in &c.figures {
        h.push_str(&format!("<p><a href=\"{f}\"><img src=\"{f}\" alt=\"{f}\"></a></p>", f = escape(f)));
    }
    h + "</div>"
}

pub fn claims_html(claims: &[Claim]) -> String {
    let mut h = String::from(HEAD);
    h.push_str(&summary_table(claims));
    for c in claims {
        h.push_str(&claim_section(c));
    }
    h.push_str("</body></html>\n");
    h
}
