#!/usr/bin/env bash
# Makes the PKI of one skilld deployment for DDS Security, with the openssl command:
#   DIR/ca.pem, DIR/private/ca_key.pem     one CA, the identity CA and the permissions CA
#   DIR/governance.p7s                     signed: authentication required, everything encrypted
#   DIR/NAME/{cert.pem,key.pem,permissions.p7s,security.yaml}   for each identity:
#     skilld (role server), each operator (may call skilld: write requests, read replies and state)
#     and each observer (may read the state only)
# security.yaml is the `security:` section for skilld's config, or for skillctl --security.
# Keys are written with mode 0600, every file atomically. DIR must lie outside the repository.
# Run it again with new names to add identities: the CA and existing identities are kept.
#
#   scripts/make_pki.sh DIR [--operators "alice bob"] [--observers "carol"] [--days N]
set -euo pipefail
umask 077

usage() { echo "usage: $0 DIR [--operators \"NAME...\"] [--observers \"NAME...\"] [--days N]" >&2; exit 2; }
[ $# -ge 1 ] || usage
dir=$1; shift
operators="operator1 operator2"
observers="observer1"
days=365
while [ $# -gt 0 ]; do
  case $1 in
    --operators) operators=${2?}; shift 2 ;;
    --observers) observers=${2?}; shift 2 ;;
    --days) days=${2:?}; shift 2 ;;
    *) usage ;;
  esac
done
[[ $days =~ ^[1-9][0-9]*$ ]] || { echo "make_pki: --days must be a positive integer, got '$days'" >&2; exit 2; }
for name in skilld $operators $observers; do
  [[ $name =~ ^[A-Za-z0-9_.-]{1,40}$ ]] || { echo "make_pki: identity name '$name' must be 1-40 of [A-Za-z0-9_.-]" >&2; exit 2; }
done
command -v openssl > /dev/null || { echo "make_pki: needs the openssl command (apt-get install openssl)" >&2; exit 2; }

repo=$(cd "$(dirname "$0")/.." && pwd -P)
dir=$(realpath -m "$dir")
case "$dir/" in
  "$repo/"*) echo "make_pki: $dir is inside the repository $repo; keys never go there" >&2; exit 2 ;;
esac
mkdir -p "$dir/private"
work=$(mktemp -d "$dir/.make_pki.XXXXXX")
trap 'rm -rf "$work"' EXIT

# Moves a finished file into place (same file system: atomic); keys keep mode 0600, the rest 0644.
place() {
  local from=$1 to=$2 mode=$3
  chmod "$mode" "$from"
  mv -f "$from" "$to"
}

sign() {  # sign IN.xml OUT.p7s: S/MIME, signed by the CA, as the access control plugin reads it
  openssl smime -sign -in "$1" -text -out "$work/signed.p7s" -signer "$dir/ca.pem" \
    -inkey "$dir/private/ca_key.pem" 2> "$work/openssl.log" || { cat "$work/openssl.log" >&2; exit 1; }
  place "$work/signed.p7s" "$2" 0644
}

if [ ! -f "$dir/ca.pem" ]; then
  openssl ecparam -name prime256v1 -genkey -noout -out "$work/ca_key.pem"
  openssl req -x509 -new -key "$work/ca_key.pem" -sha256 -days 3650 -subj "/O=FLSD/CN=FLSD deployment CA" \
    -out "$work/ca.pem"
  place "$work/ca_key.pem" "$dir/private/ca_key.pem" 0600
  place "$work/ca.pem" "$dir/ca.pem" 0644
fi

cat > "$work/governance.xml" << 'EOF'
<?xml version="1.0" encoding="utf-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>SIGN</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
EOF
sign "$work/governance.xml" "$dir/governance.p7s"

# topics TAG NAME...: a <publish> or <subscribe> rule for these topics, in every partition.
topics() {
  local tag=$1; shift
  echo "        <$tag><topics>"
  for t in "$@"; do echo "          <topic>$t</topic>"; done
  echo "        </topics><partitions><partition>*</partition></partitions></$tag>"
}

# identity NAME ROLE: a key, a certificate from the CA, signed permissions for the role, security.yaml.
identity() {
  local name=$1 role=$2 out="$dir/$1"
  [ -f "$out/cert.pem" ] && return 0
  mkdir -p "$out"
  openssl ecparam -name prime256v1 -genkey -noout -out "$work/key.pem"
  openssl req -new -key "$work/key.pem" -subj "/O=FLSD/CN=$name" -out "$work/req.csr"
  openssl x509 -req -in "$work/req.csr" -CA "$dir/ca.pem" -CAkey "$dir/private/ca_key.pem" -CAcreateserial \
    -CAserial "$dir/private/ca.srl" -sha256 -days "$days" -out "$work/cert.pem" 2> "$work/openssl.log" ||
    { cat "$work/openssl.log" >&2; exit 1; }
  local subject not_before not_after
  subject=$(openssl x509 -in "$work/cert.pem" -noout -subject -nameopt RFC2253 | sed 's/^subject=//')
  not_before=$(date -u +%Y-%m-%dT%H:%M:%S)
  not_after=$(date -u -d "+$days days" +%Y-%m-%dT%H:%M:%S)
  {
    echo '<?xml version="1.0" encoding="utf-8"?>'
    echo '<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">'
    echo '  <permissions>'
    echo "    <grant name=\"$role:$name\">"
    echo "      <subject_name>$subject</subject_name>"
    echo "      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>"
    echo '      <allow_rule>'
    echo '        <domains><id_range><min>0</min><max>230</max></id_range></domains>'
    case $role in
      server)
        topics publish flsd/reply flsd/state
        topics subscribe flsd/request ;;
      operator)  # and Cyclone's ddsperf topics, so that `skillctl bench` can compare with it
        topics publish flsd/request 'DDSPerf*'
        topics subscribe flsd/reply flsd/state 'DDSPerf*' ;;
      observer)
        topics subscribe flsd/state ;;
    esac
    echo '      </allow_rule>'
    echo '      <default>DENY</default>'
    echo '    </grant>'
    echo '  </permissions>'
    echo '</dds>'
  } > "$work/permissions.xml"
  sign "$work/permissions.xml" "$out/permissions.p7s"
  cat > "$work/security.yaml" << EOF
# DDS Security for $name ($role), made by scripts/make_pki.sh: skilld's config section, or skillctl --security.
security:
  enabled: true
  identity_ca: $dir/ca.pem
  identity_certificate: $out/cert.pem
  private_key: $out/key.pem
  permissions_ca: $dir/ca.pem
  governance: $dir/governance.p7s
  permissions: $out/permissions.p7s
EOF
  place "$work/key.pem" "$out/key.pem" 0600
  place "$work/security.yaml" "$out/security.yaml" 0644
  place "$work/cert.pem" "$out/cert.pem" 0644  # last: its presence marks the identity complete
}

identity skilld server
for name in $operators; do identity "$name" operator; done
for name in $observers; do identity "$name" observer; done
echo "make_pki: $dir: CA, governance, and identities skilld (server), ${operators:-no operators} (operator), ${observers:-no observers} (observer)"
