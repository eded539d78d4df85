-- Wireshark dissector for the SICK LD-OEM host protocol as ldoem speaks it (docs/host-protocol.md).
-- Protocol and display-filter name: ldoem. Where it applies:
--   * TCP port 49152 (preference ldoem.tcp_port): "02 55 53 50" header, 32-bit length, payload, XOR checksum, reassembled
--     across segments (host-protocol.md section 4);
--   * ISO-TP payloads on CAN ids 0x6C0/0x6C1 (D1), as a subdissector of Wireshark's ISO 15765
--     dissector: tshark -o iso15765.can.ids:1728-1729 -d iso15765.subdissector,ldoem_isotp
--   * the serial framing and LPT records of ldoem captures: ldoem_serial.lua (load both files).
-- Install: copy ldoem.lua and ldoem_serial.lua to ~/.local/lib/wireshark/plugins/ (docs/wireshark.md).

local ldoem = Proto("ldoem", "SICK LD-OEM host protocol")

local services = {
  [0x0101] = "GET_IDENTIFICATION", [0x0102] = "GET_STATUS", [0x0104] = "GET_SIGNAL", [0x0105] = "SET_SIGNAL",
  [0x0106] = "LD_REGISTER_APPLICATION", [0x0201] = "SET_CONFIG", [0x0202] = "GET_CONFIG",
  [0x0203] = "SET_TIME_ABS", [0x0204] = "SET_TIME_REL", [0x0205] = "GET_SYNC_CLOCK", [0x0209] = "SET_FILTER",
  [0x020A] = "SET_FUNCTION", [0x020B] = "GET_FUNCTION", [0x0301] = "GET_PROFILE", [0x0302] = "CANCEL_PROFILE",
  [0x0401] = "DO_RESET", [0x0402] = "TRANS_IDLE", [0x0403] = "TRANS_ROTATE", [0x0404] = "TRANS_MEASURE",
  [0x0601] = "COM_ATTACH", [0x0602] = "COM_DETACH", [0x0603] = "COM_INITIALIZE", [0x0604] = "COM_OUTPUT",
  [0x0605] = "COM_DATA", [0x0701] = "DIR", [0x0702] = "SAVE", [0x0703] = "LOAD", [0x0704] = "DELETE",
  [0x0801] = "MONITOR_RUN", [0x0802] = "MONITOR_PROFILE_LOG", [0xFF00] = "SERVICE_FAILURE",
}
local code_names = {}
for code, name in pairs(services) do
  code_names[code] = name
  if code ~= 0xFF00 then code_names[code + 0x8000] = name .. " reply" end
end
code_names[0x8301] = "PROFILE"

local sensor_modes = { [1] = "IDLE", [2] = "ROTATE", [3] = "MEASURE", [4] = "ERROR" }
local motor_modes = { [0] = "OK", [4] = "spin too low", [9] = "spin too high", [11] = "stopped or encoder error" }
local failure_reasons = { [1] = "unknown service", [2] = "wrong length", [3] = "not allowed in this state",
                          [4] = "parameter out of range", [5] = "framing error", [6] = "flash write failed" }
local ident_items = { [0x00] = "LD part number", [0x01] = "LD name", [0x02] = "LD version", [0x03] = "LD serial number",
                      [0x04] = "EDM serial number", [0x10] = "firmware part number", [0x11] = "firmware name",
                      [0x12] = "firmware version", [0x20] = "application part number", [0x21] = "application name",
                      [0x22] = "application version" }
local config_keys = { [0x0000] = "ARCNET (historical)", [0x0001] = "RS-232/422", [0x0002] = "CAN (D1)", [0x0004] = "ARCNET",
                      [0x0005] = "Ethernet", [0x0010] = "global", [0x0011] = "interlace" }
local sector_functions = { [0] = "not initialised", [1] = "no measurement", [2] = "reserved", [3] = "normal measurement",
                           [4] = "reference measurement" }
local reset_levels = { [0] = "full reset", [1] = "restart", [2] = "halt to IDLE", [0x10] = "reload APD setting" }
local measure_codes = { [0] = "OK, measuring", [1] = "maximum pulse frequency too high", [2] = "mean pulse frequency too high",
                        [3] = "sector borders not configured correctly", [4] = "sector borders not a multiple of the step" }
local bauds = { [1] = "4800", [2] = "9600", [3] = "19200", [4] = "38400", [5] = "57600", [6] = "115200" }
local can_bitrates = { [1] = "125 kbit/s", [2] = "250 kbit/s", [3] = "500 kbit/s", [4] = "1 Mbit/s" }

local f = {
  magic = ProtoField.bytes("ldoem.tcp.magic", "Header"),
  length = ProtoField.uint32("ldoem.tcp.length", "Payload length", base.DEC),
  checksum = ProtoField.uint8("ldoem.tcp.checksum", "XOR checksum", base.HEX),
  checksum_ok = ProtoField.bool("ldoem.tcp.checksum_ok", "Checksum correct"),
  service = ProtoField.uint16("ldoem.service", "Service", base.HEX, code_names),
  reply = ProtoField.bool("ldoem.reply", "Reply", 16, nil, 0x8000),
  group = ProtoField.uint16("ldoem.group", "Group", base.HEX, nil, 0x7F00),
  ident_item = ProtoField.uint16("ldoem.ident.item", "Identification item", base.HEX, ident_items),
  ident_text = ProtoField.string("ldoem.ident.text", "Identification text"),
  port = ProtoField.uint16("ldoem.port", "Port value", base.HEX),
  port_led_a = ProtoField.bool("ldoem.port.led_a", "LED 0 yellow A", 16, nil, 0x0001),
  port_led_b = ProtoField.bool("ldoem.port.led_b", "LED 1 yellow B", 16, nil, 0x0002),
  port_led_green = ProtoField.bool("ldoem.port.led_green", "LED 2 green", 16, nil, 0x0004),
  port_led_red = ProtoField.bool("ldoem.port.led_red", "LED 3 red", 16, nil, 0x0008),
  port_outputs = ProtoField.uint16("ldoem.port.outputs", "Switching outputs 0..3", base.HEX, nil, 0x00F0),
  result = ProtoField.uint16("ldoem.result", "Result", base.HEX, { [0] = "success", [1] = "refused", [0xFFFF] = "request invalid" }),
  config_key = ProtoField.uint16("ldoem.config.key", "Configuration key", base.HEX, config_keys),
  baud = ProtoField.uint16("ldoem.config.baud", "Baud rate", base.DEC, bauds),
  parity = ProtoField.uint16("ldoem.config.parity", "Parity", base.DEC, { [0] = "none", [1] = "even", [2] = "odd" }),
  stop_bits = ProtoField.uint16("ldoem.config.stop_bits", "Stop bits", base.DEC),
  data_bits = ProtoField.uint16("ldoem.config.data_bits", "Data bits", base.DEC),
  can_bitrate = ProtoField.uint16("ldoem.config.can_bitrate", "CAN bit rate", base.DEC, can_bitrates),
  can_request_id = ProtoField.uint16("ldoem.config.can_request_id", "Request CAN id", base.HEX),
  can_response_id = ProtoField.uint16("ldoem.config.can_response_id", "Response CAN id", base.HEX),
  can_block_size = ProtoField.uint16("ldoem.config.can_block_size", "ISO-TP block size", base.DEC),
  can_st_min = ProtoField.uint16("ldoem.config.can_st_min", "ISO-TP STmin (ms)", base.DEC),
  eth_ip = ProtoField.ipv4("ldoem.config.ip", "IP address"),
  eth_mask = ProtoField.ipv4("ldoem.config.mask", "Subnet mask"),
  eth_gateway = ProtoField.ipv4("ldoem.config.gateway", "Gateway"),
  eth_node = ProtoField.uint16("ldoem.config.node_id", "Node id", base.DEC),
  eth_port = ProtoField.uint16("ldoem.config.tcp_port", "Transparent TCP port", base.DEC),
  sensor_id = ProtoField.uint16("ldoem.config.sensor_id", "Sensor id", base.DEC),
  motor_speed = ProtoField.uint16("ldoem.config.motor_speed", "Motor speed (Hz)", base.DEC),
  angle_step = ProtoField.uint16("ldoem.config.angle_step", "Angle step (1/16 deg)", base.DEC),
  interlace = ProtoField.uint16("ldoem.config.interlace", "Interlace mode", base.DEC),
  config_data = ProtoField.bytes("ldoem.config.data", "Key fields"),
  time = ProtoField.uint16("ldoem.time", "Clock (ms)", base.DEC),
  time_delta = ProtoField.int16("ldoem.time_delta", "Clock change (ms)", base.DEC),
  filter_item = ProtoField.uint16("ldoem.filter.item", "Filter item", base.DEC, { [1] = "near-field suppression" }),
  filter_value = ProtoField.uint16("ldoem.filter.value", "Filter value", base.DEC, { [0] = "off", [1] = "on" }),
  sector = ProtoField.uint16("ldoem.sector.number", "Sector", base.DEC),
  sector_function = ProtoField.uint16("ldoem.sector.function", "Sector function", base.DEC, sector_functions),
  sector_stop = ProtoField.uint16("ldoem.sector.stop", "Sector stop (1/16 deg)", base.DEC),
  sector_stop_deg = ProtoField.double("ldoem.sector.stop_deg", "Sector stop (deg)"),
  flash = ProtoField.uint16("ldoem.sector.flash", "Flash flag", base.DEC, { [1] = "store in flash" }),
  profile_count = ProtoField.uint16("ldoem.request.profiles", "Profiles requested (0 = stream)", base.DEC),
  reset_level = ProtoField.uint16("ldoem.reset.level", "Reset level", base.HEX, reset_levels),
  speed = ProtoField.uint16("ldoem.rotate.speed", "Motor speed (Hz, 0 = configured)", base.DEC),
  measure_code = ProtoField.uint16("ldoem.measure.return_code", "TRANS_MEASURE return code", base.DEC, measure_codes),
  status_block = ProtoField.bytes("ldoem.status.block", "Status block"),
  status_byte = ProtoField.uint8("ldoem.status.byte", "Status byte", base.HEX),
  sensor_mode = ProtoField.uint8("ldoem.status.sensor_mode", "Sensor mode", base.DEC, sensor_modes, 0x0F),
  motor_mode = ProtoField.uint8("ldoem.status.motor_mode", "Motor mode", base.HEX, motor_modes, 0xF0),
  failure_request = ProtoField.uint16("ldoem.failure.request", "Refused request", base.HEX, code_names),
  failure_reason = ProtoField.uint16("ldoem.failure.reason", "Failure reason", base.HEX, failure_reasons),
  parameters = ProtoField.bytes("ldoem.parameters", "Parameters"),
}
local fmt_bits = {
  { 0x0001, "sent", "PROFILESENT" }, { 0x0002, "count", "PROFILECOUNT" }, { 0x0004, "layer", "LAYERNUM" },
  { 0x0008, "sector", "SECTORNUM" }, { 0x0010, "step", "DIRSTEP" }, { 0x0020, "points", "POINTNUM" },
  { 0x0040, "tstart", "TSTART" }, { 0x0080, "startdir", "STARTDIR" }, { 0x0100, "distance", "DISTANCE" },
  { 0x0200, "direction", "DIRECTION" }, { 0x0400, "echo", "ECHO" }, { 0x0800, "tend", "TEND" },
  { 0x1000, "enddir", "ENDDIR" }, { 0x2000, "senstat", "SENSTAT" }, { 0x4000, "bit14", "bit 14 (unused)" },
  { 0x8000, "bit15", "bit 15 (unused)" },
}
f.format = ProtoField.uint16("ldoem.profile.format", "Profile format", base.HEX)
for _, bit in ipairs(fmt_bits) do
  f["format_" .. bit[2]] = ProtoField.bool("ldoem.profile.format." .. bit[2], bit[3], 16, nil, bit[1])
end
for _, def in ipairs({
  { "p_sectors", "sector_count", "Sector blocks" }, { "p_sent", "sent", "PROFILESENT" },
  { "p_count", "count", "PROFILECOUNT" }, { "p_layer", "layer", "LAYERNUM" }, { "p_sector", "sector", "SECTORNUM" },
  { "p_step", "step", "DIRSTEP (1/16 deg)" }, { "p_points", "points", "POINTNUM" }, { "p_tstart", "tstart", "TSTART (ms)" },
  { "p_startdir", "startdir", "STARTDIR (1/16 deg)" }, { "p_distance", "distance", "DISTANCE (1/256 m)" },
  { "p_direction", "direction", "DIRECTION (1/16 deg)" }, { "p_echo", "echo", "ECHO" }, { "p_tend", "tend", "TEND (ms)" },
  { "p_enddir", "enddir", "ENDDIR (1/16 deg)" },
}) do
  f[def[1]] = ProtoField.uint16("ldoem.profile." .. def[2], def[3], base.DEC)
end
f.p_block = ProtoField.bytes("ldoem.profile.block", "Sector block")
f.p_point = ProtoField.bytes("ldoem.profile.point", "Point")
f.p_distance_m = ProtoField.double("ldoem.profile.distance_m", "Distance (m)")
f.p_direction_deg = ProtoField.double("ldoem.profile.direction_deg", "Direction (deg)")
f.p_total = ProtoField.uint32("ldoem.profile.total_points", "Points in this profile", base.DEC)
ldoem.fields = f

local e = {
  bad_checksum = ProtoExpert.new("ldoem.expert.bad_checksum", "Bad XOR checksum", expert.group.CHECKSUM, expert.severity.ERROR),
  bad_length = ProtoExpert.new("ldoem.expert.bad_length", "Length does not match the layout", expert.group.PROTOCOL, expert.severity.ERROR),
  too_large = ProtoExpert.new("ldoem.expert.too_large", "Payload above the 5816 bytes of D3", expert.group.PROTOCOL, expert.severity.WARN),
  unknown_service = ProtoExpert.new("ldoem.expert.unknown_service", "Unknown service code", expert.group.UNDECODED, expert.severity.WARN),
  garbage = ProtoExpert.new("ldoem.expert.garbage", "Bytes before a 02 55 53 50 header", expert.group.SEQUENCE, expert.severity.WARN),
  failure = ProtoExpert.new("ldoem.expert.service_failure", "SERVICE_FAILURE reply (D2)", expert.group.RESPONSE_CODE, expert.severity.NOTE),
  bad_status = ProtoExpert.new("ldoem.expert.bad_status", "Device reports ERROR or a motor fault", expert.group.RESPONSE_CODE, expert.severity.WARN),
}
ldoem.experts = e

-- Shared with ldoem_serial.lua (same Lua state): the serial dissector decodes its payloads here.
_G.ldoem_shared = { proto = ldoem, fields = f, experts = e, code_names = code_names }

local function deg(ticks) return ticks / 16.0 end
-- word(): adds a WORD field and returns its value.
local function word(tree, field, tvb, offset) tree:add(field, tvb(offset, 2)); return tvb(offset, 2):uint() end

local function add_status_block(tree, tvb, offset)
  local block = tree:add(f.status_block, tvb(offset, 4))
  block:add(f.status_byte, tvb(offset + 3, 1))
  block:add(f.sensor_mode, tvb(offset + 3, 1))
  block:add(f.motor_mode, tvb(offset + 3, 1))
  local status = tvb(offset + 3, 1):uint()
  if bit32.band(status, 0x0F) == 4 or bit32.rshift(status, 4) ~= 0 then
    block:add_proto_expert_info(e.bad_status)
  end
  return status
end

-- Checks that a layout of `need` bytes fits exactly (or, for requests without parameters, with
-- the trailing 0x0000 WORD serial drivers append, D2).
local function check_length(tree, tvb, need, allow_trailing_zero)
  local have = tvb:len()
  if have == need then return true end
  if allow_trailing_zero and have == need + 2 and tvb(need, 2):uint() == 0 then return true end
  tree:add_proto_expert_info(e.bad_length, string.format("Length %d, layout needs %d", have, need))
  return have >= need
end

local dissect_profile -- defined below

local function dissect_config_fields(tree, tvb, offset, key)
  local left = tvb:len() - offset
  if key == 0x0001 and left >= 8 then
    word(tree, f.baud, tvb, offset); word(tree, f.parity, tvb, offset + 2)
    word(tree, f.stop_bits, tvb, offset + 4); word(tree, f.data_bits, tvb, offset + 6)
    return offset + 8
  elseif key == 0x0002 and left >= 10 then
    word(tree, f.can_bitrate, tvb, offset); word(tree, f.can_request_id, tvb, offset + 2)
    word(tree, f.can_response_id, tvb, offset + 4); word(tree, f.can_block_size, tvb, offset + 6)
    word(tree, f.can_st_min, tvb, offset + 8)
    return offset + 10
  elseif key == 0x0005 and left >= 28 then
    for i, field in ipairs({ f.eth_ip, f.eth_mask, f.eth_gateway }) do
      local at = offset + (i - 1) * 8
      local octets = {}
      for k = 0, 3 do octets[k + 1] = tvb(at + 2 * k + 1, 1):uint() end
      tree:add(field, tvb(at, 8), Address.ip(table.concat(octets, ".")))
    end
    word(tree, f.eth_node, tvb, offset + 24); word(tree, f.eth_port, tvb, offset + 26)
    return offset + 28
  elseif key == 0x0010 and left >= 6 then
    word(tree, f.sensor_id, tvb, offset); word(tree, f.motor_speed, tvb, offset + 2)
    word(tree, f.angle_step, tvb, offset + 4)
    return offset + 6
  elseif key == 0x0011 and left >= 2 then
    word(tree, f.interlace, tvb, offset)
    return offset + 2
  end
  if left > 0 then tree:add(f.config_data, tvb(offset, left)) end
  return tvb:len()
end

local function add_port(tree, tvb, offset)
  local item = tree:add(f.port, tvb(offset, 2))
  for _, field in ipairs({ f.port_led_a, f.port_led_b, f.port_led_green, f.port_led_red, f.port_outputs }) do item:add(field, tvb(offset, 2)) end
end

-- Requests (bit 15 clear). Returns a short summary for the Info column.
local function dissect_request(tree, tvb, code)
  local n = tvb:len()
  if code == 0x0101 then
    if check_length(tree, tvb, 4) then return ident_items[word(tree, f.ident_item, tvb, 2)] or "" end
  elseif code == 0x0105 then
    if check_length(tree, tvb, 4) then add_port(tree, tvb, 2) end
  elseif code == 0x0201 then
    if n >= 4 then
      local key = word(tree, f.config_key, tvb, 2)
      dissect_config_fields(tree, tvb, 4, key)
      return config_keys[key] or ""
    end
    check_length(tree, tvb, 4)
  elseif code == 0x0202 then
    if check_length(tree, tvb, 4) then return config_keys[word(tree, f.config_key, tvb, 2)] or "" end
  elseif code == 0x0203 then
    if check_length(tree, tvb, 4) then word(tree, f.time, tvb, 2) end
  elseif code == 0x0204 then
    if check_length(tree, tvb, 4) then tree:add(f.time_delta, tvb(2, 2)) end
  elseif code == 0x0209 then
    if check_length(tree, tvb, 6) then word(tree, f.filter_item, tvb, 2); word(tree, f.filter_value, tvb, 4) end
  elseif code == 0x020A then
    if check_length(tree, tvb, 10) then
      word(tree, f.sector, tvb, 2); word(tree, f.sector_function, tvb, 4)
      local stop = word(tree, f.sector_stop, tvb, 6)
      tree:add(f.sector_stop_deg, tvb(6, 2), deg(stop)):set_generated()
      word(tree, f.flash, tvb, 8)
    end
  elseif code == 0x020B then
    if check_length(tree, tvb, 4) then return "sector " .. word(tree, f.sector, tvb, 2) end
  elseif code == 0x0301 then
    if check_length(tree, tvb, 6) then
      local count = word(tree, f.profile_count, tvb, 2)
      local item = tree:add(f.format, tvb(4, 2))
      for _, bit in ipairs(fmt_bits) do item:add(f["format_" .. bit[2]], tvb(4, 2)) end
      return string.format("%s, format 0x%04X", count == 0 and "stream" or (count .. " profiles"), tvb(4, 2):uint())
    end
  elseif code == 0x0401 then
    if check_length(tree, tvb, 4) then return reset_levels[word(tree, f.reset_level, tvb, 2)] or "" end
  elseif code == 0x0403 then
    if check_length(tree, tvb, 4) then return word(tree, f.speed, tvb, 2) .. " Hz" end
  elseif code == 0x0102 or code == 0x0104 or code == 0x0205 or code == 0x0302 or code == 0x0402 or code == 0x0404 then
    check_length(tree, tvb, 2, true)
  elseif n > 2 then
    tree:add(f.parameters, tvb(2, n - 2))
  end
  return ""
end

-- Replies (bit 15 set) and SERVICE_FAILURE.
local function dissect_reply(tree, tvb, code, pinfo)
  local n = tvb:len()
  local request = bit32.band(code, 0x7FFF)
  if code == 0xFF00 then
    if check_length(tree, tvb, 6) then
      word(tree, f.failure_request, tvb, 2)
      local reason = word(tree, f.failure_reason, tvb, 4)
      tree:add_proto_expert_info(e.failure)
      return failure_reasons[reason] or string.format("reason 0x%04X", reason)
    end
  elseif request == 0x0301 then
    return dissect_profile(tree, tvb, pinfo)
  elseif request == 0x0101 then
    if n > 2 then tree:add(f.ident_text, tvb(2, n - 2)); return (tvb(2, n - 2):string():gsub("%z.*", "")) end
  elseif request == 0x0102 or request == 0x0302 or request == 0x0402 or request == 0x0403 then
    if check_length(tree, tvb, 6) then
      local status = add_status_block(tree, tvb, 2)
      return sensor_modes[bit32.band(status, 0x0F)] or ""
    end
  elseif request == 0x0404 then
    if check_length(tree, tvb, 8) then
      add_status_block(tree, tvb, 2)
      return measure_codes[word(tree, f.measure_code, tvb, 6)] or ""
    end
  elseif request == 0x0104 then
    if check_length(tree, tvb, 4) then add_port(tree, tvb, 2) end
  elseif request == 0x0105 or request == 0x0201 then
    if check_length(tree, tvb, 4) then word(tree, f.result, tvb, 2) end
  elseif request == 0x0202 then
    if n >= 4 then
      local key = word(tree, f.config_key, tvb, 2)
      dissect_config_fields(tree, tvb, 4, key)
      return config_keys[key] or ""
    end
    check_length(tree, tvb, 4)
  elseif request == 0x0203 or request == 0x0204 or request == 0x0205 then
    if check_length(tree, tvb, 4) then return word(tree, f.time, tvb, 2) .. " ms" end
  elseif request == 0x0209 then
    if check_length(tree, tvb, 4) then word(tree, f.filter_item, tvb, 2) end
  elseif request == 0x020A then
    if check_length(tree, tvb, 4) then
      local value = tvb(2, 2):uint()
      if value == 0xFFFF then word(tree, f.result, tvb, 2); return "request invalid" end
      word(tree, f.sector, tvb, 2)
    end
  elseif request == 0x020B then
    if check_length(tree, tvb, 8) then
      word(tree, f.sector, tvb, 2); word(tree, f.sector_function, tvb, 4)
      local stop = word(tree, f.sector_stop, tvb, 6)
      tree:add(f.sector_stop_deg, tvb(6, 2), deg(stop)):set_generated()
    end
  elseif request == 0x0401 then
    if check_length(tree, tvb, 4) then return reset_levels[word(tree, f.reset_level, tvb, 2)] or "" end
  elseif n > 2 then
    tree:add(f.parameters, tvb(2, n - 2))
  end
  return ""
end

-- A profile telegram (0x8301): every field the format's bits switch on (host-protocol.md 3.2).
dissect_profile = function(tree, tvb, pinfo)
  local n = tvb:len()
  if n < 6 then check_length(tree, tvb, 6); return "" end
  local format = tvb(2, 2):uint()
  local item = tree:add(f.format, tvb(2, 2))
  for _, bit in ipairs(fmt_bits) do item:add(f["format_" .. bit[2]], tvb(2, 2)) end
  local has = function(mask) return bit32.band(format, mask) ~= 0 end
  local sectors = word(tree, f.p_sectors, tvb, 4)
  local offset = 6
  local function field(t, fld)
    if offset + 2 > n then return nil end
    local value = word(t, fld, tvb, offset)
    offset = offset + 2
    return value
  end
  if has(0x0001) then field(tree, f.p_sent) end
  if has(0x0002) then field(tree, f.p_count) end
  if has(0x0004) then field(tree, f.p_layer) end
  local per_point = 2 * ((has(0x0100) and 1 or 0) + (has(0x0200) and 1 or 0) + (has(0x0400) and 1 or 0))
  local block_tail = 2 * ((has(0x0800) and 1 or 0) + (has(0x1000) and 1 or 0))
  local senstat = has(0x2000) and 4 or 0
  local total = 0
  for s = 1, sectors do
    if offset > n then break end
    local block = tree:add(f.p_block, tvb(offset, 0)):set_text("Sector block " .. s)
    local start = offset
    local function bfield(fld) return field(block, fld) end
    if has(0x0008) then bfield(f.p_sector) end
    if has(0x0010) then bfield(f.p_step) end
    local points
    if has(0x0020) then points = bfield(f.p_points) end
    if has(0x0040) then bfield(f.p_tstart) end
    if has(0x0080) then bfield(f.p_startdir) end
    if not points and per_point > 0 and sectors == 1 then
      -- No POINTNUM: the count follows from the length (only possible with one sector block).
      points = math.floor((n - offset - block_tail - senstat) / per_point)
    end
    points = points or 0
    if per_point > 0 and offset + points * per_point > n then
      block:add_proto_expert_info(e.bad_length, string.format("%d points do not fit the telegram", points))
      points = math.floor((n - offset) / per_point)
    end
    for p = 1, points do
      local point = block:add(f.p_point, tvb(offset, per_point)):set_text("Point " .. p)
      if has(0x0100) then
        local raw = tvb(offset, 2):uint()
        point:add(f.p_distance, tvb(offset, 2))
        point:add(f.p_distance_m, tvb(offset, 2), raw / 256.0)
        offset = offset + 2
      end
      if has(0x0200) then
        local raw = tvb(offset, 2):uint()
        point:add(f.p_direction, tvb(offset, 2))
        point:add(f.p_direction_deg, tvb(offset, 2), deg(raw))
        offset = offset + 2
      end
      if has(0x0400) then point:add(f.p_echo, tvb(offset, 2)); offset = offset + 2 end
    end
    total = total + points
    if has(0x0800) then bfield(f.p_tend) end
    if has(0x1000) then bfield(f.p_enddir) end
    block:set_len(offset - start)
  end
  if has(0x2000) then
    if offset + 4 <= n then add_status_block(tree, tvb, offset); offset = offset + 4
    else tree:add_proto_expert_info(e.bad_length, "SENSTAT missing") end
  end
  if offset ~= n then
    tree:add_proto_expert_info(e.bad_length, string.format("%d bytes after the last field", n - offset))
  end
  tree:add(f.p_total, total):set_generated()
  return string.format("format 0x%04X, %d sectors, %d points", format, sectors, total)
end

-- One payload (service WORD + parameters), whatever the transport. Returns the Info text.
function ldoem_shared.dissect_payload(tvb, pinfo, tree)
  if tvb:len() < 2 then
    tree:add_proto_expert_info(e.bad_length, "No service code")
    return "empty telegram"
  end
  local code = tvb(0, 2):uint()
  local code_item = tree:add(f.service, tvb(0, 2))
  code_item:add(f.reply, tvb(0, 2))
  code_item:add(f.group, tvb(0, 2))
  local name = code_names[code]
  if not name then
    code_item:add_proto_expert_info(e.unknown_service)
    name = string.format("0x%04X", code)
  end
  local detail
  if bit32.band(code, 0x8000) ~= 0 then detail = dissect_reply(tree, tvb, code, pinfo)
  else detail = dissect_request(tree, tvb, code) end
  local text = name
  if detail and detail ~= "" then text = text .. " (" .. detail .. ")" end
  tree:append_text(": " .. text)
  return text
end

local function set_info(pinfo, text)
  if pinfo.private["ldoem_info"] then pinfo.cols.info:append(", " .. text); return end
  pinfo.cols.protocol = "LD-OEM"
  pinfo.cols.info = text
  pinfo.private["ldoem_info"] = "1"
end
ldoem_shared.set_info = set_info

-- TCP (section 4): frames may span segments and one segment may hold several frames.
local MAX_TCP_PAYLOAD = 5816
local MAX_ACCEPTED_PAYLOAD = 65536 -- larger lengths are not a header at all
local MAGIC = "02555350"

local function find_magic(tvb, from)
  local n = tvb:len()
  for i = from, n - 4 do
    if tvb(i, 4):bytes():tohex() == MAGIC then return i end
  end
  return nil
end

function ldoem.dissector(tvb, pinfo, tree)
  local offset = 0
  local n = tvb:len()
  while offset < n do
    if n - offset < 8 then
      pinfo.desegment_offset = offset
      pinfo.desegment_len = DESEGMENT_ONE_MORE_SEGMENT
      return n
    end
    local length = tvb(offset + 4, 4):uint()
    if tvb(offset, 4):bytes():tohex() ~= MAGIC or length > MAX_ACCEPTED_PAYLOAD then
      local next = find_magic(tvb, offset + 1) or n
      local item = tree:add(ldoem, tvb(offset, next - offset)):set_text("LD-OEM: bytes outside a frame")
      item:add_proto_expert_info(e.garbage)
      offset = next
    else
      local frame_len = 8 + length + 1
      if n - offset < frame_len then
        pinfo.desegment_offset = offset
        pinfo.desegment_len = frame_len - (n - offset)
        return n
      end
      local subtree = tree:add(ldoem, tvb(offset, frame_len))
      subtree:add(f.magic, tvb(offset, 4))
      local len_item = subtree:add(f.length, tvb(offset + 4, 4))
      if length > MAX_TCP_PAYLOAD then len_item:add_proto_expert_info(e.too_large) end
      local payload = tvb(offset + 8, length):tvb()
      local text = ldoem_shared.dissect_payload(payload, pinfo, subtree)
      local xor = 0
      local bytes = tvb(offset + 8, length):bytes()
      for i = 0, length - 1 do xor = bit32.bxor(xor, bytes:get_index(i)) end
      local sum_item = subtree:add(f.checksum, tvb(offset + 8 + length, 1))
      local ok = xor == tvb(offset + 8 + length, 1):uint()
      subtree:add(f.checksum_ok, tvb(offset + 8 + length, 1), ok):set_generated()
      if not ok then
        sum_item:add_proto_expert_info(e.bad_checksum, string.format("Bad XOR checksum (computed 0x%02X)", xor))
        text = text .. " [bad checksum]"
      end
      set_info(pinfo, text)
      offset = offset + frame_len
    end
  end
  return n
end

-- The device's TCP port: 49152 (spec 4.1) unless the preference says otherwise, for a capture
-- of a device configured to another port (Edit > Preferences > Protocols > LDOEM, or
-- `tshark -o ldoem.tcp_port:4000`); `-d tcp.port==4000,ldoem` (Decode As) works too.
ldoem.prefs.tcp_port = Pref.uint("TCP port", 49152, "The LD-OEM's TCP port (49152 unless configured otherwise)")
local registered_port = ldoem.prefs.tcp_port
DissectorTable.get("tcp.port"):add(registered_port, ldoem)
function ldoem.prefs_changed()
  if ldoem.prefs.tcp_port == registered_port then return end
  local tcp = DissectorTable.get("tcp.port")
  tcp:remove(registered_port, ldoem)
  registered_port = ldoem.prefs.tcp_port
  if registered_port ~= 0 then tcp:add(registered_port, ldoem) end
end

-- ISO-TP (D1): the reassembled message is a bare payload.
local ldoem_isotp = Proto("ldoem_isotp", "SICK LD-OEM over ISO-TP (D1)")
function ldoem_isotp.dissector(tvb, pinfo, tree)
  local subtree = tree:add(ldoem, tvb())
  set_info(pinfo, ldoem_shared.dissect_payload(tvb, pinfo, subtree))
  return tvb:len()
end
local isotp_table = DissectorTable.get("iso15765.subdissector")
if isotp_table then isotp_table:add_for_decode_as(ldoem_isotp) end
