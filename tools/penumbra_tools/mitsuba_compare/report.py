"""The comparison's markdown report (machine, throughput, agreement, time-to-error) and
its place in docs/PERFORMANCE.md, between the results markers of the Results section."""
import os
import platform
import re
import subprocess
import time

from penumbra_tools.mitsuba_compare.paths import DOC, PENUMBRA


def machine_info():
    import mitsuba as mi
    model = platform.processor()
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        m = re.search(r"Model name:\s*(.+)", out)
        model = m.group(1).strip() if m else model
    except OSError:
        pass
    dev = " ".join(line.strip() for line in
                   subprocess.run([PENUMBRA, "devices"], capture_output=True, text=True).stdout.splitlines())
    mesa = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "mesa-vulkan-drivers"], capture_output=True,
                          text=True).stdout.strip()
    import drjit as dr
    return {"cpu": model, "cores": os.cpu_count(), "device": dev, "mesa": mesa, "mitsuba": mi.__version__,
            "drjit": dr.__version__, "llvm": os.environ.get("DRJIT_LIBLLVM_PATH", "(default)"),
            "load": os.getloadavg(), "date": time.strftime("%Y-%m-%d %H:%M %Z")}


def fmt(x, d=2):
    if x is None:
        return "n/a"
    if isinstance(x, str):
        return x
    if x != 0 and (abs(x) < 10 ** -d or abs(x) >= 1e5):
        return f"{x:.2e}"
    return f"{x:.{d}f}"


def report(info, results, args):
    L = []
    L.append(f"Measured {info['date']} by `tools/bench/bench-mitsuba{' ' + ' '.join(args.argv) if args.argv else ''}`.")
    reused = [r["name"] for r in results if r.get("reused")]
    if reused:
        when = sorted({r["timed_at"] for r in results if r.get("reused")})
        L.append(f"Throughput and start-up of {', '.join(reused)} come from the previous full run "
                 f"({', '.join(when)}, build/mitsuba-compare/results.json); agreement and time-to-error "
                 "were measured now.")
    L.append("")
    L.append(f"- CPU: {info['cpu']}, {info['cores']} cores (load average at the end: "
             f"{', '.join(f'{x:.1f}' for x in info['load'])}; the machine is shared, so timings are noisy: medians)")
    L.append(f"- Penumbra device: {info['device'].lstrip('* ')}; Mesa {info['mesa']}")
    L.append(f"- Mitsuba {info['mitsuba']} (Dr.Jit {info['drjit']}), llvm_ad_rgb on {os.path.basename(info['llvm'])}, "
             f"and scalar_rgb")
    L.append("")
    L.append("Throughput (median of the timed renders, Msamples/s = width x height x spp / render time; "
             "ratio = Penumbra / Mitsuba; Penumbra's rays per sample (camera, shadow and BRDF rays) are counted "
             "by `penumbra_bench --count-rays`, Mitsuba's `direct` integrator traces the same rays per sample, so "
             "its Mrays/s is its Msamples/s times Penumbra's rays per sample):")
    L.append("")
    L.append("| scene | res, spp | Penumbra Ms/s | Mitsuba llvm Ms/s | Mitsuba scalar Ms/s | Penumbra/llvm | "
             "Penumbra/scalar | rays/sample | Mrays/s: Penumbra / llvm | start-up s: Penumbra / llvm / scalar |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        p, ml, ms = r["penumbra"], r.get("llvm"), r.get("scalar")
        sp = lambda m: m["msps"] if m else None  # noqa: E731
        ratio = lambda a, b: f"{a / b:.2f}" if a and b else "n/a"  # noqa: E731
        scal = fmt(sp(ms)) + (f" ({ms['spp']} spp)" if ms and ms["spp"] != r["spp"] else "")
        rps = p.get("rays_per_sample")
        rays = (f"{rps:.2f} | {fmt(p['mrps'])} / {fmt(sp(ml) * rps if ml else None)}" if rps else "n/a | n/a")
        L.append(f"| {r['name']} | {r['width']}x{r['height']}, {r['spp']} | {fmt(sp(p))} | {fmt(sp(ml))} | {scal} | "
                 f"{ratio(sp(p), sp(ml))} | {ratio(sp(p), sp(ms))} | {rays} | "
                 f"{fmt(p['startup_s'], 1)} / {fmt(ml and ml['startup_s'], 1)} / {fmt(ms and ms['startup_s'], 1)} |")
    L.append("")
    L.append("Render seconds (median, all runs in brackets) and start-up detail:")
    L.append("")
    for r in results:
        for key, label in (("penumbra", "Penumbra"), ("llvm", "Mitsuba llvm"), ("scalar", "Mitsuba scalar")):
            m = r.get(key)
            if not m:
                continue
            extra = ""
            if key != "penumbra":
                extra = f"; import {m['import_s']:.2f} s, scene load {m['load_s']:.2f} s, first render {m['first_s']:.2f} s"
            L.append(f"- {r['name']}, {label}: {m['median_s']:.3f} s [{', '.join(f'{t:.2f}' for t in m['times'])}] "
                     f"at {m['spp']} spp; start-up {m['startup_s']:.2f} s{extra}")
    L.append("")
    L.append(f"Image agreement at {args.quality_scale:g} x film size: Penumbra reference ({args.ref_spp} spp, seed 4242) "
             f"vs Mitsuba llvm ({args.ref_spp} spp); noise floor = two independent Mitsuba renders of "
             f"{args.ref_spp} spp compared with each other. Block = 8x8 pixel means. Verdict: match when "
             "relMSE <= 3x floor, block relMSE <= 4x block floor and channel means within 2%.")
    L.append("")
    L.append("| scene | relMSE P vs M | floor M vs M | block relMSE | block floor | mean ratio M/P (r,g,b) | "
             "worst 8x8 block (x,y): rel. diff / noise | verdict |")
    L.append("|---|---|---|---|---|---|---|---|")
    for r in results:
        a = r.get("agreement")
        if not a:
            continue
        w = a["worst_block"]
        L.append(f"| {r['name']} | {fmt(a['relmse'], 4)} | {fmt(a['noise_relmse'], 4)} | {fmt(a['block_relmse'], 5)} | "
                 f"{fmt(a['block_noise_relmse'], 5)} | {', '.join(f'{x:.3f}' for x in a['mean_ratio'])} | "
                 f"({w['x']},{w['y']}) of {w['image'][0]}x{w['image'][1]}: {w['rel_diff']:.3f} / {w['noise']:.3f} | "
                 f"**{r['verdict']}** |")
    L.append("")
    tte = [r for r in results if r.get("tte")]
    if tte:
        L.append(f"Time-to-error at {args.quality_scale:g} x film size: render seconds (excluding start-up) to reach "
                 f"the target relMSE against the Penumbra reference ({args.target:g}, or 10x the reference's own "
                 "noise where that is larger), log-log interpolated between the renders at 1, 2, 4, ... spp "
                 "that bracket the first render below it (spp, seconds, relMSE of each render in brackets; "
                 f"the seconds are the median of {args.tte_runs} renders of the same image; one image per level, "
                 "so a firefly can make one level worse than the one before):")
        L.append("")
        L.append("Penumbra renders with its default sampler (Owen-scrambled Sobol') and with `sampler.type` "
                 "independent; Mitsuba llvm with its default `independent` sampler and with its low-discrepancy "
                 "`ldsampler`. Ratios are Penumbra Sobol' over each Mitsuba variant.")
        L.append("")
        L.append("| scene | target relMSE | Penumbra Sobol' s | Penumbra independent s | Mitsuba llvm independent s | "
                 "Mitsuba llvm ldsampler s | Penumbra / llvm independent | Penumbra / llvm ldsampler |")
        L.append("|---|---|---|---|---|---|---|---|")
        for r in tte:
            tp, ti = r["tte"]["penumbra_s"], r["tte"].get("penumbra_independent_s")
            tm, tl = r["tte"]["llvm_s"], r["tte"].get("llvm_ld_s")
            q = lambda a, b: f"{a / b:.2f}" if a and b else "n/a"  # noqa: E731
            L.append(f"| {r['name']} | {r['tte']['target']:.4g} | {fmt(tp, 3)} | {fmt(ti, 3)} | {fmt(tm, 3)} | "
                     f"{fmt(tl, 3)} | {q(tp, tm)} | {q(tp, tl)} |")
        L.append("")
        for r in tte:
            for key in ("penumbra", "penumbra_independent", "llvm", "llvm_ld"):
                pts = r["tte"].get(key + "_points")
                if pts is None:
                    continue
                L.append(f"- {r['name']} {key}: " + ", ".join(f"({s}, {t:.3f}, {e:.4f})" for s, t, e in pts))
        L.append("")
    notes = [n for r in results for n in r.get("notes", [])]
    if notes:
        L.append("Notes:")
        L.append("")
        L += [f"- {n}" for n in notes]
        L.append("")
    return "\n".join(L)


def write_doc(text):
    os.makedirs(os.path.dirname(DOC), exist_ok=True)
    doc = open(DOC).read() if os.path.exists(DOC) else "# Performance\n\n## Results\n\n"
    begin, end = "<!-- results:begin -->", "<!-- results:end -->"
    block = f"{begin}\n{text}\n{end}"
    if begin in doc and end in doc:
        doc = doc[:doc.index(begin)] + block + doc[doc.index(end) + len(end):]
    elif "## Results" in doc:
        i = doc.index("## Results") + len("## Results")
        doc = doc[:i] + "\n\n" + block + doc[i:]
    else:
        doc += "\n## Results\n\n" + block + "\n"
    with open(DOC, "w") as f:
        f.write(doc)
