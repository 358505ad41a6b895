#!/usr/bin/env bash
# Fetch a Debian *source* package into a folder without touching the system's apt
# configuration: the deb-src entries are derived from the machine's own deb entries
# (same hosts, keys and components) and live in a private apt state folder.
#
#   fetch-debian-source.sh PACKAGE SUITE DEST
#     SUITE: "native" = the suites this machine already uses (Debian 12: bookworm),
#            or a codename (e.g. trixie) to swap in for the machine's main suite.
# Prints the path of the unpacked source tree on its last line of stdout.
set -euo pipefail
pkg=$1 suite=$2 dest=$3
mkdir -p "$dest"
dest=$(cd "$dest" && pwd)
state="$dest/.apt-$suite"
mkdir -p "$state/lists/partial" "$state/archives/partial"
src_list="$state/sources.list"
: >"$src_list"

native=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")

emit() { # uri suite components signed_by
    local opts=""
    [ -n "$4" ] && opts="[signed-by=$4] "
    if [ "$suite" = native ]; then
        echo "deb-src ${opts}$1 $2 $3" >>"$src_list"
    elif [ "$2" = "$native" ]; then
        # Only the main suite has a counterpart in another release; security and
        # updates suites are skipped.
        echo "deb-src ${opts}$1 $suite $3" >>"$src_list"
    fi
}

# One-line format (sources.list and *.list files).
for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    while read -r type rest; do
        [ "$type" = deb ] || continue
        signed=""
        if [[ $rest == \[* ]]; then
            optstr=${rest%%]*}; rest=${rest#*] }
            [[ $optstr =~ signed-by=([^ \]]+) ]] && signed=${BASH_REMATCH[1]}
        fi
        read -r uri s comps <<<"$rest"
        case "$uri" in *debian*) emit "$uri" "$s" "$comps" "$signed" ;; esac
    done <"$f"
done

# deb822 format (*.sources files).
for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    awk 'BEGIN{RS=""; FS="\n"}
         { t=u=s=c=k=""
           for(i=1;i<=NF;i++){ if($i ~ /^#/) continue
             split($i, kv, ": ")
             if(kv[1]=="Types") t=kv[2]; else if(kv[1]=="URIs") u=kv[2];
             else if(kv[1]=="Suites") s=kv[2]; else if(kv[1]=="Components") c=kv[2];
             else if(kv[1]=="Signed-By") k=kv[2]; }
           if (t ~ /deb/ && u ~ /debian/) { n=split(s, ss, " "); for(j=1;j<=n;j++) print u "\t" ss[j] "\t" c "\t" k } }' "$f" |
    while IFS=$'\t' read -r uri s comps signed; do emit "$uri" "$s" "$comps" "$signed"; done
done

[ -s "$src_list" ] || { echo "fetch-debian-source: no Debian deb entries found in /etc/apt" >&2; exit 1; }

apt_opts=(-o "Dir::Etc::SourceList=$src_list" -o "Dir::Etc::SourceParts=/nonexistent"
          -o "Dir::State::Lists=$state/lists" -o "Dir::Cache::Archives=$state/archives"
          -o "Dir::State::status=/var/lib/dpkg/status" -o "APT::Sandbox::User=root")
apt-get "${apt_opts[@]}" -q update >&2
cd "$dest"
# The version `apt-get source` picks: the highest one in the index.
ver=""
for v in $(apt-cache "${apt_opts[@]}" showsrc "$pkg" 2>/dev/null |
           awk -v p="$pkg" '/^Package: /{cur=$2} /^Version: /&&cur==p{print $2}'); do
    if [ -z "$ver" ] || dpkg --compare-versions "$v" gt "$ver"; then ver=$v; fi
done
[ -n "$ver" ] || { echo "fetch-debian-source: no source package $pkg in $suite" >&2; exit 1; }
ver=${ver#*:}; upver=${ver%-*}
tree="$dest/$pkg-$upver"
if [ -d "$tree" ]; then echo "$tree"; exit 0; fi

# Some archives this runs against serve the upstream tarball but not the .dsc or the
# Debian diff (seen for trixie's and sid's meshlab). apt checks every file it does get
# against the signed index, so the tarball alone is still trustworthy: unpack it without
# Debian's patches rather than fail, and say so.
apt-get "${apt_opts[@]}" -q source --download-only "$pkg" >&2 || true
dsc="$dest/${pkg}_$ver.dsc"
if [ -f "$dsc" ]; then
    dpkg-source --no-check -x "$dsc" "$tree" >&2
else
    orig=$(ls "$dest/${pkg}_$upver".orig.tar.* 2>/dev/null | grep -v '\.asc$' | head -n1 || true)
    [ -n "$orig" ] || { echo "fetch-debian-source: could not download $pkg $ver" >&2; exit 1; }
    echo "fetch-debian-source: WARNING: ${pkg}_$ver.dsc is not available; unpacking $(basename "$orig")" \
         "without Debian's patches" >&2
    mkdir -p "$tree.partial"
    tar -xf "$orig" -C "$tree.partial" --strip-components=1
    mv "$tree.partial" "$tree"
fi
echo "$tree"
