#!/usr/bin/python3
"""Parse a Prometheus text page with Debian's python3-prometheus-client.

Usage: parse_metrics.py FILE
Prints one line per sample, "name{label="value",...} value" with labels
sorted, after the families' names and types ("# family NAME TYPE").
Exit 1 with the parser's message when the page does not parse.
"""
import sys

from prometheus_client.parser import text_string_to_metric_families

with open(sys.argv[1]) as f:
    text = f.read()
try:
    for family in text_string_to_metric_families(text):
        print(f"# family {family.name} {family.type}")
        for s in family.samples:
            labels = ",".join(f'{k}="{v}"' for k, v in sorted(s.labels.items()))
            print(f"{s.name}{{{labels}}} {s.value!r}")
except Exception as e:  # the parser raises ValueError and others
    print(f"{sys.argv[1]}: does not parse: {e}")
    sys.exit(1)
