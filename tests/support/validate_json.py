#!/usr/bin/python3
"""Validate one JSON document against one of spinewatch's JSON Schemas.

Usage: validate_json.py SCHEMA_DIR SCHEMA_NAME FILE
The other schemas of SCHEMA_DIR can be referred to by their $id (the state
document refers to the posture line's schema). Exit 0 when valid; else the
first problem.
"""
import glob
import json
import sys

import jsonschema

schema_dir, name, path = sys.argv[1], sys.argv[2], sys.argv[3]
store = {}
for file in glob.glob(f"{schema_dir}/*.schema.json"):
    with open(file) as f:
        s = json.load(f)
    store[s["$id"]] = s
with open(f"{schema_dir}/{name}.schema.json") as f:
    schema = json.load(f)
jsonschema.Draft202012Validator.check_schema(schema)
with open(path) as f:
    try:
        doc = json.load(f)
    except json.JSONDecodeError as e:
        print(f"{path}: not JSON: {e}")
        sys.exit(1)
try:  # jsonschema >= 4.18
    from referencing import Registry, Resource
    registry = Registry().with_resources((i, Resource.from_contents(s)) for i, s in store.items())
    validator = jsonschema.Draft202012Validator(schema, registry=registry)
except ImportError:  # Debian 12's 4.10
    resolver = jsonschema.RefResolver.from_schema(schema, store=store)
    validator = jsonschema.Draft202012Validator(schema, resolver=resolver)
errors = sorted(validator.iter_errors(doc), key=str)
if errors:
    e = errors[0]
    print(f"{path}: {'/'.join(str(p) for p in e.absolute_path)}: {e.message}")
    sys.exit(1)
