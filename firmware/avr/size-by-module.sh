#!/usr/bin/env bash
# Where the flash and static RAM of an AVR image go, by source file and by
# area (CANopen core, gateway, Modbus, MCP2515 driver, Uno ports, Arduino
# core, C runtime). The shipped images are linked with LTO, which merges code
# across files; this builds the same image without LTO (MB2CO_AVR_LTO=OFF,
# into build/avr-modules) so that the link map names the file of every
# section. Without LTO the image is about 10 % bigger than the shipped one:
# the shares are what counts, the last line compares the totals.
# Usage: firmware/avr/size-by-module.sh [image]   (default mb2co-gateway)
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
image=${1:-mb2co-gateway}
build=${MB2CO_AVR_MODULES_DIR:-build/avr-modules}
shipped=${MB2CO_AVR_BUILD_DIR:-build/avr}

cmake -S firmware/avr -B "$build" -G Ninja -DMB2CO_AVR_LTO=OFF \
  -DCMAKE_TOOLCHAIN_FILE="$root/cmake/avr-toolchain.cmake" -DCMAKE_BUILD_TYPE=MinSizeRel >/dev/null
if ! grep -qx -- "$image" "$build/images.txt"; then
  echo "size-by-module: no image '$image' (images: $(tr '\n' ' ' <"$build/images.txt"))" >&2
  exit 2
fi
cmake --build "$build" --target "$image" >/dev/null

shipped_flash=""
if [[ -f "$shipped/$image.elf" ]]; then
  read -r text data _ < <(avr-size --format=berkeley "$shipped/$image.elf" | tail -n 1)
  shipped_flash=$((text + data))
fi

python3 - "$build/$image.map" "$image" "$shipped_flash" <<'EOF'
import collections, re, sys

map_path, image, shipped_flash = sys.argv[1], sys.argv[2], sys.argv[3]
text = open(map_path).read()
# Only the part after "Linker script and memory map" places sections.
text = text[text.index("Linker script and memory map"):]

# An input section: " .name  0xADDR  0xSIZE  file", the name possibly on a
# line of its own. Flash sections sit below 0x800000, RAM at 0x800100 up.
section = re.compile(r"^ (\.[^\s]+)\s*\n?\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)\s+(\S+)", re.M)

def area(path):
    name = path.rsplit("/", 1)[-1]
    lib = re.match(r"lib(\w+)\.a\((.+)\)", name)
    if lib:
        library, member = lib.groups()
        member = member.replace(".obj", "").replace(".o", "")
        if library == "arduino_core":
            return "Arduino core", member
        # Ours are mb2co_avr_<profile>_<area> (firmware/avr/CMakeLists.txt):
        # the area is the last word; anything else is the toolchain's.
        areas = {
            "canopen": "shared/canopen",
            "gateway": "shared/gateway",
            "modbus": "shared/modbus",
            "ionode": "shared/ionode",
            "serialnet": "shared/serialnet",
            "mcp2515": "firmware/mcp2515",
            "port": "firmware/avr/port",
        }
        if library.startswith("mb2co_avr_"):
            return areas.get(library.rsplit("_", 1)[-1], "mb2co (other)"), member
        return "C runtime (libgcc, libc)", member
    if "crt" in name:
        return "C runtime (libgcc, libc)", name
    return "sketch", name.replace(".obj", "")

flash = collections.Counter()
ram = collections.Counter()
placed = re.compile(r"\.(text|progmem|rodata|data|bss|noinit|vectors|init\d|fini\d|ctors|dtors|"
                    r"trampolines|jumptables|lowtext|hightext)\b")
for name, addr, size, path in section.findall(text):
    size = int(size, 16)
    if size == 0 or path.startswith("0x") or not placed.match(name):
        continue  # debug information, comments: not in the image
    key = area(path)
    if int(addr, 16) >= 0x800000:
        ram[key] += size
        if name.startswith(".data"):
            flash[key] += size  # initial values are stored in flash too
    else:
        flash[key] += size

by_area = collections.Counter()
ram_by_area = collections.Counter()
for (a, _), n in flash.items():
    by_area[a] += n
for (a, _), n in ram.items():
    ram_by_area[a] += n
total = sum(flash.values())
total_ram = sum(ram.values())

print(f"== {image} without LTO: flash by area (bytes, share), static RAM")
for a, n in by_area.most_common():
    print(f"{a:28s} {n:6d}  {100.0 * n / total:5.1f} %   RAM {ram_by_area[a]:5d}")
print(f"{'total':28s} {total:6d}            RAM {total_ram:5d}")
print()
print(f"== {image} without LTO: flash by source file (>= 100 B)")
for (a, member), n in flash.most_common():
    if n < 100:
        break
    print(f"{n:6d}  {a}/{member}")
if shipped_flash:
    print()
    print(f"shipped image (LTO): {shipped_flash} B flash; this build: {total} B "
          f"({100.0 * (total - int(shipped_flash)) / int(shipped_flash):+.1f} %)")
EOF
