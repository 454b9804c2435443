// Reads Parquet files with two independent readers, hyparquet and DuckDB (npm packages of
// package.json, installed by scripts/install-deps.sh), and prints what each read as one JSON
// object on stdout: {FILE: {hyparquet: {schema, rows}, duckdb: {types, rows, metadata}}}.
// Integers become JSON numbers (the datasets' values are below 2^53); a list is an array.
// Used by tests/io/parquet_test.cc and tests/io/lerobot_test.cc (docs/datasets.md).
// Usage: node tests/datasets/read_parquet.mjs FILE...
import { asyncBufferFromFile, parquetMetadataAsync, parquetReadObjects } from 'hyparquet';
import { DuckDBInstance } from '@duckdb/node-api';

function plain(value) {
  if (typeof value === 'bigint') return Number(value);
  if (Array.isArray(value)) return value.map(plain);
  if (ArrayBuffer.isView(value)) return Array.from(value, plain);
  if (value !== null && typeof value === 'object') {
    if ('items' in value) return value.items.map(plain);  // DuckDB LIST / ARRAY values
    if (value instanceof Uint8Array) return Buffer.from(value).toString();
    return Object.fromEntries(Object.entries(value).map(([k, v]) => [k, plain(v)]));
  }
  return value;
}

const out = {};
const instance = await DuckDBInstance.create(':memory:');
const connection = await instance.connect();
for (const file of process.argv.slice(2)) {
  const buffer = await asyncBufferFromFile(file);
  const metadata = await parquetMetadataAsync(buffer);
  const schema = metadata.schema.map((e) => ({
    name: e.name,
    type: e.type ?? null,
    repetition_type: e.repetition_type ?? null,
    converted_type: e.converted_type ?? null,
    logical_type: e.logical_type?.type ?? null,
  }));
  const hyparquetRows = (await parquetReadObjects({ file: buffer })).map(plain);
  const quoted = `'${file.replaceAll("'", "''")}'`;
  const described = await connection.runAndReadAll(`DESCRIBE SELECT * FROM read_parquet(${quoted})`);
  const types = Object.fromEntries(
    described.getRowObjects().map((r) => [r.column_name, r.column_type]));
  const data = await connection.runAndReadAll(`SELECT * FROM read_parquet(${quoted})`);
  const kv = await connection.runAndReadAll(
    `SELECT decode(key) AS key, decode(value) AS value FROM parquet_kv_metadata(${quoted})`);
  const kvObject = Object.fromEntries(kv.getRowObjects().map((r) => [r.key, r.value]));
  out[file] = {
    hyparquet: { schema, num_rows: Number(metadata.num_rows), rows: hyparquetRows },
    duckdb: { types, rows: data.getRowObjects().map(plain), metadata: kvObject },
  };
}
process.stdout.write(JSON.stringify(out));
