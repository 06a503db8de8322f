"""The benchmark report as the table scripts/bench.sh prints."""

from __future__ import annotations

from typing import Any

import rounds


# ---------------------------------------------------------------------------- the report
def table(report: dict[str, Any]) -> str:
    lines = []
    if report.get("speech"):
        from speech import table as speech_table

        lines += speech_table(report["speech"])
    if report.get("gc"):
        from gc_policy import table as gc_table

        lines += gc_table(report["gc"])
    lat = report.get("latency")
    if lat:
        lines.append("change-to-visible latency (2 hops)    p50        p90        p99")
        for k in ("dsr", "volatile", "raw", "fdatasync"):
            v = lat[k]
            lines.append(
                f"  {k:<35} {v['p50_ms']:6.3f} ms  {v['p90_ms']:6.3f} ms  {v['p99_ms']:6.3f} ms"
            )
        paced = lat.get("fdatasync_paced")
        if paced:
            lines.append(f"  {'fdatasync, 1 ms apart':<35} {paced['p50_ms']:6.3f} ms")
        for kind, steps in lat.get("stages", {}).items():
            shown = ", ".join(f"{k[:-3]} {v:.3f}" for k, v in steps.items())
            lines.append(f"  {kind} steps (p50 ms): {shown}")
        lines.append(
            f"  symbolic/raw p50 {lat['ratio_p50']:.2f}x, p99 {lat['ratio_p99']:.2f}x; volatile/"
            f"raw p50 {lat['ratio_p50_volatile']:.2f}x (medians of {lat['rounds']['count']} "
            f"interleaved rounds of {lat['rounds']['samples_per_round']}, spreads below); "
            f"symbolic/(raw + fdatasync) p50 {lat['ratio_p50_durable_floor']:.2f}x  (target "
            f"{lat['targets']}: {'met' if lat['met'] else 'NOT met'})"
        )
    tp = report.get("throughput")
    if tp:
        lines.append(
            "throughput                 agents  dsr tx/s  dsr ops/s (batched)  raw msgs/s"
            "  (deltas applied / messages received by every subscriber)"
        )
        for k, v in tp["agents"].items():
            note = ""
            if v.get("dsr_resyncs") or v.get("dsr_delivered", 1) < 1:
                note = (
                    f"  dsr: {v['dsr_delivered']:.0%} applied one by one, "
                    f"{v['dsr_resyncs']} resync(s) from a snapshot"
                )
            if v["raw_delivered"] < 1:
                note += f"  raw: {v['raw_delivered']:.0%} received"
            lines.append(
                f"  {'':<24} {k:>6}  {v['dsr_tx_per_s']:8.0f}  "
                f"{v['dsr_batched_ops_per_s']:19.0f}  {v['raw_msgs_per_s']:10.0f}{note}"
            )
        lines.append(f"  target {tp['targets']}: {'met' if tp['met'] else 'NOT met'}")
    sc = report.get("scale")
    if sc:
        lines.append(
            "scale        nodes  set_attr us/op  edge us/op  snapshot MB  late joiner s  "
            "then all used s  model B/node  server RSS B/node"
        )
        for k, v in sc["sizes"].items():
            lines.append(
                f"  {'':<9} {k:>7}  {v['set_attr_us_per_op']:14.1f}  {v['edge_us_per_op']:10.1f}  "
                f"{v['snapshot_bytes'] / 1e6:11.2f}  {v['late_joiner_s']:13.3f}  "
                f"{v['late_joiner_then_all_used_s']:15.3f}  "
                f"{v['model_bytes_per_node']:12.0f}  "
                f"{v['server_rss_bytes_per_node']:16.0f}"
            )
        stamped = [(k, v) for k, v in sc["sizes"].items() if "stamped_late_joiner_s" in v]
        for k, v in stamped:
            lines.append(
                f"  {k} nodes, every attribute stamped (provenance): snapshot "
                f"{v['stamped_snapshot_bytes'] / 1e6:.2f} MB, late joiner "
                f"{v['stamped_late_joiner_s']:.3f} s"
            )
        lines.append(f"  target {sc['targets']}: {'met' if sc['met'] else 'NOT met'}")
    if report.get("provenance"):
        from cortex import provenance_lines

        lines += provenance_lines(report["provenance"])
    if report.get("rt_history"):
        from cortex import rt_history_lines

        lines += rt_history_lines(report["rt_history"])
    kin = report.get("kinematics")
    if kin:
        lines.append("kinematics   depth  cold q/s  cached q/s  naive numpy q/s")
        for k, v in kin["depths"].items():
            lines.append(
                f"  {'':<9} {k:>5}  {v['cold_qps']:8.0f}  {v['cached_qps']:10.0f}  "
                f"{v['naive_qps']:15.0f}"
            )
        lines.append(f"  target {kin['targets']}: {'met' if kin['met'] else 'NOT met'}")
    if report.get("restart"):
        from restart import table as restart_table

        lines += restart_table(report["restart"])
    b = report.get("barthel")
    if b:
        lines.append(
            f"barthel run (pace x{b['pace']}): completed {b['completed']}, test {b['test_s']} s, "
            f"launch wall {b['wall_s']:.1f} s, CPU {b['cpu_total_s']:.1f} s in all"
        )
        lines.append(
            "  "
            + ", ".join(
                f"{k} {v:.1f}s" for k, v in sorted(b["cpu_s"].items(), key=lambda kv: -kv[1])
            )
        )
    g = report.get("gug")
    if g:
        q, st = g["latency_quiet"], g["latency_streaming"]
        lines.append(
            f"get up & go: skeleton at 30 Hz, 14 joints ({g['frames_written_per_s']:.1f} frames/s "
            f"written of {g['frames_offered_per_s']:.1f}, {g['frames_per_tx']:.1f} a "
            f"transaction, {g['delta_bytes']} B for one)"
        )
        lines.append(
            f"  server CPU {g['server_cpu_streaming']:.1%} streaming vs {g['server_cpu_idle']:.1%}"
            " idle"
        )
        lines.append(
            f"  a Speech change's latency p50/p99 {st['p50_ms']:.3f}/{st['p99_ms']:.3f} ms "
            f"streaming vs {q['p50_ms']:.3f}/{q['p99_ms']:.3f} ms quiet"
        )
        lines.append(
            f"  journal: {g['journal_bytes_per_min'] / 1e3:.1f} kB/min while it streams "
            f"({g['volatile_share']:.0%} of the frames' transactions volatile, not journalled), "
            f"largest {g['journal_largest_bytes'] / 1e3:.1f} kB (compaction every "
            f"{g['compact_every']} journalled deltas)"
        )
        u = g["under_load"]
        ul, uq = u["latency_streaming"], u["latency_quiet"]
        lines.append(
            f"  under load ({u['busy_processes']} busy processes): "
            f"{u['frames_written_per_s']:.1f} frames/s written of "
            f"{u['frames_offered_per_s']:.1f}, {u['frames_per_tx']:.1f} a transaction; a Speech "
            f"change p50/p99 {ul['p50_ms']:.3f}/{ul['p99_ms']:.3f} ms streaming vs "
            f"{uq['p50_ms']:.3f}/{uq['p99_ms']:.3f} ms without the stream"
        )
        for load, runs in (
            (k, v) for k, v in g.get("scenarios", {}).items() if isinstance(v, dict)
        ):
            lines.append(f"  GUG scenarios at pace x{g['scenarios']['pace']}, {load}:")
            for name, v in runs.items():
                timed = f"{v['tug_seconds']:.1f} s" if v["tug_seconds"] is not None else "-"
                lines.append(
                    f"    {name:<24} {v['outcome'] or 'nothing stored':<8} {timed:>7}  "
                    f"trials {v['trials']}  wall {v['wall_s']:.0f} s"
                )
        r = g["robot"]
        lines.append(
            f"  whole robot over a GUG run (pace x{r['pace']}): completed {r['completed']}, CPU "
            f"{r['cpu_total_s']:.1f} s in all, launch wall {r['wall_s']:.1f} s"
            + (f" (Barthel run: {b['cpu_total_s']:.1f} s, {b['wall_s']:.1f} s)" if b else "")
        )
        lines.append(
            "  "
            + ", ".join(
                f"{k} {v:.1f}s" for k, v in sorted(r["cpu_s"].items(), key=lambda kv: -kv[1])
            )
        )
    c = report.get("camera")
    if c:
        q, st, hop = c["latency_quiet"], c["latency_streaming"], c["hop"]
        lines.append(
            f"camera: 640x480 colour + depth at 30 Hz with the skeleton at 30 Hz: images "
            f"{c['frames_offered_per_s']:.1f}/s offered, {c['frames_written_per_s']:.1f} written, "
            f"{c['frames_delivered_per_s']:.1f} delivered whole to a replica that asks for the "
            f"bytes ({c['frames_unfetched']} not in time, {c['reader_resyncs']} resyncs); "
            f"skeleton {c['skeleton_frames_written_per_s']:.1f} frames/s written"
        )
        lines.append(
            f"  server CPU {c['server_cpu_streaming']:.1%} streaming vs {c['server_cpu_idle']:.1%}"
            f" idle; a Speech change p50/p99 {st['p50_ms']:.3f}/{st['p99_ms']:.3f} ms streaming "
            f"vs {q['p50_ms']:.3f}/{q['p99_ms']:.3f} ms quiet "
            f"(p99 x{st['p99_ms'] / q['p99_ms']:.2f})"
        )
        lines.append(
            f"  one hop of a frame: {hop['blob_ms']:.2f} ms as blobs vs {hop['inline_ms']:.2f} ms "
            f"as base64 JSON ({hop['inline_json_bytes'] / 1e6:.1f} MB of text)"
        )
    signed = report.get("signed")
    if signed:
        lines.append("signed DSR traffic (enforce) next to unsigned (off), same run")
        for mode in ("off", "enforce"):
            v = signed[mode]
            lines.append(
                f"  {mode:<8} latency p50 {v['latency']['p50_ms']:.3f} ms, p99 "
                f"{v['latency']['p99_ms']:.3f} ms; {v['tx_per_s']:,.0f} tx/s (1 agent); "
                f"Barthel run {v['barthel_cpu_s']:.1f} CPU s (server "
                f"{v['barthel_server_cpu_s'] or 0:.1f})"
                + ("" if v["barthel_completed"] else "  [the run did not complete]")
            )
        c = signed["cost"]
        lines.append(
            f"  cost: p50 {c['p50_ms']:+.3f} ms, p99 {c['p99_ms']:+.3f} ms, throughput "
            f"x{c['throughput_ratio']:.2f}, Barthel CPU x{c['barthel_cpu_ratio']:.2f}"
        )
    if report.get("ratios"):
        lines.append("ratios: the median of the per-round ratios of interleaved rounds (rounds.py)")
        lines += [f"  {name:<38} {rounds.shown(r)}" for name, r in report["ratios"].items()]
    for name, why in report.get("failed", {}).items():
        lines.append(f"section {name} FAILED: {why}")
    return "\n".join(lines)
