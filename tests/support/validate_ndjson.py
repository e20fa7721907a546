#!/usr/bin/python3
"""Validate NDJSON lines against spinewatch's JSON Schemas (docs/).

Usage: validate_ndjson.py SCHEMA_DIR FILE
Posture lines are checked against posture.schema.json; hello, reply,
summary and alert lines against hello.schema.json, reply.schema.json,
summary.schema.json and alert.schema.json. Exit 0 when every line is valid; else the first problem.
"""
import json
import sys

import jsonschema

schema_dir, path = sys.argv[1], sys.argv[2]
schemas = {}
for name in ("posture", "hello", "reply", "summary", "alert"):
    with open(f"{schema_dir}/{name}.schema.json") as f:
        schemas[name] = json.load(f)
        jsonschema.Draft202012Validator.check_schema(schemas[name])

count = 0
with open(path) as f:
    for lineno, line in enumerate(f, 1):
        if not line.strip():
            print(f"{path}:{lineno}: empty line")
            sys.exit(1)
        try:
            obj = json.loads(line)
        except json.JSONDecodeError as e:
            print(f"{path}:{lineno}: not JSON: {e}")
            sys.exit(1)
        kind = obj.get("class") if isinstance(obj, dict) else None
        schema = schemas.get(kind, schemas["posture"])
        errors = sorted(jsonschema.Draft202012Validator(schema).iter_errors(obj), key=str)
        if errors:
            e = errors[0]
            where = "/".join(str(p) for p in e.absolute_path)
            print(f"{path}:{lineno}: {where}: {e.message}")
            sys.exit(1)
        count += 1
if count == 0:
    print(f"{path}: no lines")
    sys.exit(1)
