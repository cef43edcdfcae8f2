//! `claims.html`: every claim with its paper, statement, rule, our numbers, the verdict and its
//! figures, readable offline beside the report's `index.html`.

use super::claims::{Claim, Verdict};
use crate::report::escape;

fn colour(v: Verdict) -> &'static str {
    match v {
        Verdict::Holds => "#009E73",
        Verdict::Partly => "#E69F00",
        Verdict::DoesNotHold => "#D55E00",
    }
}

pub fn claims_html(claims: &[Claim]) -> String {
    let mut h = String::from(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>shadowtruth: the papers' claims</title>\
         <style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}\
         .claim{border:1px solid #ccc;border-radius:6px;padding:1em;margin:1em 0}\
         .verdict{color:#fff;padding:.2em .6em;border-radius:4px;font-weight:bold}\
         pre{background:#f6f6f6;padding:.6em;overflow:auto}img{max-width:100%}</style></head><body>\
         <h1>The papers' claims, measured</h1><p>Each verdict is computed from the measured numbers by \
         the rule shown. The runs behind them are in <a href=\"index.html\">the report</a>.</p>",
    );
    h.push_str("<table><tr><th>claim</th><th>verdict</th></tr>");
    for c in claims {
        h.push_str(&format!(
            "<tr><td><a href=\"#{id}\">{id}</a></td><td><span class=\"verdict\" style=\"background:{}\">{}</span></td></tr>",
            colour(c.verdict),
            c.verdict.name(),
            id = escape(&c.id)
        ));
    }
    h.push_str("</table>");
    for c in claims {
        let numbers = serde_json::to_string_pretty(&c.numbers).unwrap_or_default();
        h.push_str(&format!(
            "<div class=\"claim\" id=\"{id}\"><h2>{id} <span class=\"verdict\" style=\"background:{col}\">{v}</span></h2>\
             <p><i>{paper}</i></p><p>{statement}</p><p><b>Rule:</b> {rule}</p><pre>{numbers}</pre>",
            id = escape(&c.id),
            col = colour(c.verdict),
            v = c.verdict.name(),
            paper = escape(&c.paper),
            statement = escape(&c.statement),
            rule = escape(&c.rule),
            numbers = escape(&numbers),
        ));
        for f in &c.figures {
            h.push_str(&format!("<p><a href=\"{f}\"><img src=\"{f}\" alt=\"{f}\"></a></p>", f = escape(f)));
        }
        h.push_str("</div>");
    }
    h.push_str("</body></html>\n");
    h
}
