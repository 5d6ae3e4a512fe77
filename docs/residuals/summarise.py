#!/usr/bin/env python3
"""Prints the summary table of every residual analysis in this folder (docs/residuals/README.md)."""
import json
import pathlib

here = pathlib.Path(__file__).resolve().parent


def pct(before, after):
    return 100.0 * (after - before) / before if before else float("nan")


def selected(d):
    """The selected effects as (id, found): found is True / False by the effect's evidence, None in older reports."""
    return [(e["effect"], e["fingerprint_found"]) if isinstance(e, dict) else (e, None) for e in d["selected"]]


def selected_ids(d):
    return [e for e, _ in selected(d)]


def label(found):
    return {True: "found", False: "correction of unshown cause", None: "evidence not read"}[found]


def fmt_effects(d):
    sel = selected(d)
    if not sel:
        return "nothing"
    parts = []
    for e, found in sel:
        params = d["selected_params"].get(e, {})
        parts.append(f"{e} **{label(found)}** (" +
                     ", ".join(f"{k.split('.', 1)[-1]} {v:.3g}" for k, v in params.items()) + ")")
    return " + ".join(parts)


def fmt_at_bound(d):
    """The answer's own parameters at a bound (model-form symptoms of the answer), or '-'."""
    b = d.get("answer_at_bound", [])
    if not b:
        return "-"
    return ", ".join(f"{p['param']} {p['value']:.3g} ({p['bound']}{', default' if p['is_default'] else ''})"
                     for p in b)


def best_rejected(d):
    cands = [c for c in d["candidates"] if c["effect"] not in selected_ids(d) and c["improvement_pct"] is not None]
    if not cands:
        return "-"
    c = max(cands, key=lambda c: c["improvement_pct"])
    lo, hi = c["ci95_pct"]
    why = ""
    fp = c.get("fingerprint")
    if fp and not fp["found"]:
        why = f" — fingerprint not found ({fp['param']} {fp['calibration']:.3g} / {fp['validation']:.3g}: " + \
              fp["verdict"].split(" (")[0] + ")" if fp["calibration"] is not None and fp["validation"] is not None \
              else " — fingerprint not found (" + fp["verdict"] + ")"
    elif c.get("model_form_symptom"):
        why = " — model-form symptom: " + c["veto"].split(": ", 1)[-1].replace(" at a bound of its physical range", " at a bound")
    elif c.get("veto", "").startswith("screened"):
        why = " — screened"
    return f"{c['effect']} {c['improvement_pct']:+.1f} % [{lo:.1f}, {hi:.1f}]{why}"


def model_form(d):
    """The model-form round (issue 17): the selected variant and its validation RMSE, or '-' (none tried)."""
    forms = d.get("model_forms")
    if not forms:
        return "-"
    sel = d.get("model_form_selected", "")
    if not sel:
        return "none passes"
    c = next(c for c in forms if c["model"] == sel)
    held = " (dilation kernel held)" if d.get("model_form_held") else ""
    return f"{sel}{held} {c['validation_rmse_px']:.3f} ({-c['improvement_pct']:+.1f} %)"


def goal_table(runs):
    """Per twin set and motion: HydroShear's loop answer (the selected form with the effects selected on it)
    against the lowest of the published models' base fits in this folder (FOTS re-impl., TacSL, HydroShear)."""
    print()
    print("Per twin set and motion: HydroShear's answer (the model form the loop selects, with the effects selected")
    print("on it), against the lowest of the published models' base fits above (FOTS re-impl., TacSL, HydroShear).")
    print()
    print("| twin set | motion | HydroShear's answer (px) | lowest published model (px) | lower |")
    print("|---|---|---|---|---|")
    for name in sorted({d["dataset"] for d in runs if d["dataset"].startswith("twin_")}):
        by = {d["model"]: d for d in runs if d["dataset"] == name}
        hs = by.get("hydroshear")
        if not hs or hs.get("after_model", "hydroshear") == "hydroshear":
            continue
        sel = hs["after_model"]
        mine = hs["after"]["by_motion"]
        for motion, m in mine.items():
            best = min(((d["before"]["by_motion"][motion]["rmse_px"], k) for k, d in by.items()
                        if motion in d["before"]["by_motion"]))
            ok = "yes" if m["rmse_px"] < best[0] else "**no**"
            print(f"| {name} | {motion} | {m['rmse_px']:.3f} ({sel}) | {best[0]:.3f} ({best[1]}) | {ok} |")


runs = []
print("| dataset | model | the loop's answer | validation RMSE before -> after (px) | change | model form selected (val. RMSE px) | effects selected on it: found or a correction of unshown cause (fitted parameters) | answer's parameters at a bound | best candidate not selected (95 % CI) |")
print("|---|---|---|---|---|---|---|---|---|")
for f in sorted(here.glob("*/residual.json")):
    d = json.loads(f.read_text())
    runs.append(d)
    b, a = d["before"]["validation_rmse_px"], d["after"]["validation_rmse_px"]
    answer = d.get("after_model", d["model"])
    print(f"| [{d['dataset']}]({f.parent.name}/report.md) | {d['model']} | `{answer}` | {b:.3f} -> {a:.3f} | "
          f"{pct(b, a):+.1f} % | {model_form(d)} | {fmt_effects(d)} | {fmt_at_bound(d)} | {best_rejected(d)} |")
goal_table(runs)
