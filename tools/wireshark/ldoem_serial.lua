-- Serial framing and LPT records of ldoem captures (docs/capture.md), for Wireshark. Needs
-- ldoem.lua loaded first (Wireshark loads plugins in name order; with tshark pass both:
-- -X lua_script:ldoem.lua -X lua_script:ldoem_serial.lua).
--   LINKTYPE_USER0: one direction byte (0 host to device, 1 device to host), then the line's
--     bytes: STX, WORDs as 4 hex digits, CRC-16 WORD, ETX (host-protocol.md section 4);
--   LINKTYPE_USER1: one direction byte (0), then the LPT data-register values written (D8).
local shared = assert(_G.ldoem_shared, "ldoem_serial.lua needs ldoem.lua loaded first")

local serial = Proto("ldoem_serial", "SICK LD-OEM serial framing")
local directions = { [0] = "host to device", [1] = "device to host" }
local sf = {
  direction = ProtoField.uint8("ldoem_serial.direction", "Direction", base.DEC, directions),
  package = ProtoField.bytes("ldoem_serial.package", "Package"),
  address = ProtoField.uint16("ldoem_serial.address", "Address", base.HEX),
  length = ProtoField.uint16("ldoem_serial.length", "Length (WORDs)", base.DEC),
  package_id = ProtoField.uint16("ldoem_serial.package_id", "Package id / W2", base.HEX),
  packages = ProtoField.uint16("ldoem_serial.packages", "Packages in this reply", base.DEC),
  remaining = ProtoField.uint16("ldoem_serial.remaining", "Continuation counter", base.DEC),
  crc = ProtoField.uint16("ldoem_serial.crc", "CRC-16", base.HEX),
  crc_ok = ProtoField.bool("ldoem_serial.crc_ok", "CRC correct"),
}
serial.fields = sf
local se = {
  bad_crc = ProtoExpert.new("ldoem_serial.bad_crc", "Bad serial CRC-16", expert.group.CHECKSUM, expert.severity.ERROR),
  bad_hex = ProtoExpert.new("ldoem_serial.bad_hex", "Not a hex digit, or not whole WORDs", expert.group.PROTOCOL, expert.severity.ERROR),
  bad_length = ProtoExpert.new("ldoem_serial.bad_length", "Length WORD does not match the package", expert.group.PROTOCOL, expert.severity.ERROR),
  incomplete = ProtoExpert.new("ldoem_serial.incomplete", "Reply packages missing", expert.group.SEQUENCE, expert.severity.WARN),
}
serial.experts = se

-- CRC-16 of the protocol: polynomial 0x1021, register 0xFFFF, register-shift form, over bytes.
local crc_table = {}
for i = 0, 255 do
  local c = bit32.lshift(i, 8)
  for _ = 1, 8 do
    if bit32.band(c, 0x8000) ~= 0 then c = bit32.bxor(bit32.lshift(c, 1), 0x1021) else c = bit32.lshift(c, 1) end
  end
  crc_table[i] = bit32.band(c, 0xFFFF)
end
local function serial_crc(words, count)
  local reg = 0xFFFF
  for i = 1, count do
    for _, b in ipairs({ bit32.rshift(words[i], 8), bit32.band(words[i], 0xFF) }) do
      reg = bit32.band(bit32.bxor(bit32.bor(bit32.lshift(reg, 8), b), crc_table[bit32.rshift(reg, 8)]), 0xFFFF)
    end
  end
  return reg
end

-- Decodes the hex between STX (at `start`) and ETX; returns the WORDs or nil.
local function hex_words(tvb, start, stop)
  local text = tvb(start + 1, stop - start - 1):string()
  if #text % 4 ~= 0 or text:find("[^0-9a-fA-F]") then return nil end
  local words = {}
  for i = 1, #text, 4 do words[#words + 1] = tonumber(text:sub(i, i + 3), 16) end
  return words
end

local function words_to_tvb(words, first, last, name)
  local bytes = ByteArray.new()
  bytes:set_size(2 * (last - first + 1))
  for i = first, last do
    bytes:set_index(2 * (i - first), bit32.rshift(words[i], 8))
    bytes:set_index(2 * (i - first) + 1, bit32.band(words[i], 0xFF))
  end
  return bytes
end

function serial.dissector(tvb, pinfo, tree)
  if tvb:len() < 1 then return 0 end
  local direction = tvb(0, 1):uint()
  local root = tree:add(serial, tvb())
  root:add(sf.direction, tvb(0, 1))
  pinfo.cols.protocol = "LD-OEM serial"
  local reply = ByteArray.new() -- payload bytes of a reply spread over packages
  local expected_packages, seen_packages = 0, 0
  local offset = 1
  local n = tvb:len()
  while offset < n do
    local stx = nil
    for i = offset, n - 1 do if tvb(i, 1):uint() == 0x02 then stx = i; break end end
    if not stx then break end
    local etx = nil
    for i = stx + 1, n - 1 do if tvb(i, 1):uint() == 0x03 then etx = i; break end end
    if not etx then root:add_proto_expert_info(se.incomplete, "Package without ETX"); break end
    local package = root:add(sf.package, tvb(stx, etx - stx + 1))
    local words = hex_words(tvb, stx, etx)
    if not words or #words < 4 then
      package:add_proto_expert_info(se.bad_hex)
    else
      local count = #words
      local wtvb = words_to_tvb(words, 1, count, "words"):tvb("Serial WORDs")
      package:add(sf.address, wtvb(0, 2))
      local length = words[2]
      package:add(sf.length, wtvb(2, 2))
      local crc_item = package:add(sf.crc, wtvb(2 * (count - 1), 2))
      local computed = serial_crc(words, count - 1)
      package:add(sf.crc_ok, wtvb(2 * (count - 1), 2), computed == words[count]):set_generated()
      if computed ~= words[count] then
        crc_item:add_proto_expert_info(se.bad_crc, string.format("Bad CRC-16 (computed 0x%04X)", computed))
        shared.set_info(pinfo, "[bad CRC]")
      end
      if direction == 0 then
        -- Host to device: ADDRESS LENGTH PACKAGE CODE PARAMS... CRC; LENGTH counts LENGTH..last param.
        package:add(sf.package_id, wtvb(4, 2))
        if length ~= count - 2 then package:add_proto_expert_info(se.bad_length) end
        local payload = words_to_tvb(words, 4, count - 1):tvb("LD-OEM payload")
        shared.set_info(pinfo, shared.dissect_payload(payload, pinfo, package:add(shared.proto, payload())))
      elseif seen_packages == 0 or seen_packages >= expected_packages then
        -- First package of a reply: ADDRESS LENGTH W2 PACKAGES payload... CRC.
        package:add(sf.package_id, wtvb(4, 2))
        package:add(sf.packages, wtvb(6, 2))
        if length ~= count - 2 then package:add_proto_expert_info(se.bad_length) end
        expected_packages, seen_packages = words[4], 1
        reply = words_to_tvb(words, 5, count - 1)
      else
        -- Continuation: ADDRESS LENGTH REMAINING payload... CRC.
        package:add(sf.remaining, wtvb(4, 2))
        if length ~= count - 2 then package:add_proto_expert_info(se.bad_length) end
        seen_packages = seen_packages + 1
        reply:append(words_to_tvb(words, 4, count - 1))
      end
      if direction == 1 and seen_packages == expected_packages and seen_packages > 0 then
        local payload = reply:tvb("LD-OEM reply payload")
        -- An odd payload was padded with one 0x00 (host-protocol.md 4); the decoder ignores it.
        shared.set_info(pinfo, shared.dissect_payload(payload, pinfo, root:add(shared.proto, payload())))
        seen_packages, expected_packages = 0, 0
      end
    end
    offset = etx + 1
  end
  if direction == 1 and seen_packages > 0 and seen_packages < expected_packages then
    root:add_proto_expert_info(se.incomplete, string.format("%d of %d packages", seen_packages, expected_packages))
  end
  return n
end

local lpt = Proto("ldoem_lpt", "ldoem pseudo-LPT drive register (D8)")
local lf = {
  value = ProtoField.uint8("ldoem_lpt.value", "Data register", base.HEX),
  direction = ProtoField.bool("ldoem_lpt.dir", "DATA0 direction (tilt grows)", 8, nil, 0x01),
  clock = ProtoField.bool("ldoem_lpt.clock", "DATA1 clock", 8, nil, 0x02),
  half_step = ProtoField.bool("ldoem_lpt.half_step", "DATA2 half step", 8, nil, 0x04),
}
lpt.fields = lf
function lpt.dissector(tvb, pinfo, tree)
  local root = tree:add(lpt, tvb())
  pinfo.cols.protocol = "LD-OEM LPT"
  local values = {}
  for i = 1, tvb:len() - 1 do
    local item = root:add(lf.value, tvb(i, 1))
    item:add(lf.direction, tvb(i, 1)); item:add(lf.clock, tvb(i, 1)); item:add(lf.half_step, tvb(i, 1))
    values[#values + 1] = string.format("%02X", tvb(i, 1):uint())
  end
  pinfo.cols.info = "LPT writes " .. table.concat(values, " ")
  return tvb:len()
end

local encaps = DissectorTable.get("wtap_encap")
local user = wtap_encaps or wtap
encaps:add(user.USER0, serial)
encaps:add(user.USER1, lpt)
