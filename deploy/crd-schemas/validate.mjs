// Validates the custom resources of rendered manifests against their CRDs' schemas.
// Usage: node validate.mjs OBJECTS.json (a JSON array of Kubernetes objects); objects
// of core kinds are skipped (kubernetes-validate checks those). Exits 1 on the first
// invalid object, or if a custom kind has no schema here.
import { readFileSync } from "node:fs";
import { ServiceMonitor } from "@kubernetes-models/prometheus-operator/monitoring.coreos.com/v1/ServiceMonitor";

const models = { "monitoring.coreos.com/v1/ServiceMonitor": ServiceMonitor };
const objects = JSON.parse(readFileSync(process.argv[2], "utf8"));
let checked = 0;
for (const obj of objects) {
  const group = obj.apiVersion.includes("/") ? obj.apiVersion.split("/")[0] : "";
  if (!group.includes(".") || group.endsWith(".k8s.io")) continue; // a core kind
  const key = `${obj.apiVersion}/${obj.kind}`;
  const Model = models[key];
  const where = `${obj.kind}/${obj.metadata?.name}`;
  if (!Model) {
    console.error(`ERROR ${where}: no schema for ${key} in deploy/crd-schemas`);
    process.exit(1);
  }
  try {
    new Model(obj).validate();
  } catch (err) {
    console.error(`ERROR ${where}: ${err.message}`);
    process.exit(1);
  }
  checked += 1;
}
console.log(`crd schemas: ${checked} custom resource(s) valid`);
