#!/usr/bin/env node
// An independent CANopen peer on a SocketCAN interface, built on npm's
// `canopen` (6.x) and `socketcan` (installed in tests/peers/npm by
// scripts/deps.sh). Used by tests/peers against mb2co's own nodes.
//
// Usage: canopen_peer.js [--can IFACE] COMMAND [options]
//   client upload|download --node N --index I --sub S [--block] [--file F]
//          [--data HEX | --size BYTES] [--timeout MS] [--interval MS]
//      One SDO transfer with the server of node N (600h+N / 580h+N). Upload
//      writes the data to F (or prints it as data=HEX when it is <= 256
//      bytes); download sends F, HEX, or BYTES of the pattern below.
//      stdout, one line: ok upload|download index=I sub=S bytes=N
//        transfer=expedited|segmented|block time_s=T bytes_per_s=R [data=HEX]
//      On an SDO abort: abort upload|download index=I sub=S code=XXXXXXXX
//        transfer=... message=... and exit 1 (3 on any other failure, 2 on
//        bad usage). transfer= is the protocol the server's first answer
//        chose (upload) or the client's request (download); none when the
//        upload was refused at once.
//   server --node N [--size BYTES] [--interval MS]
//      A device with node id N answering SDO on 600h+N / 580h+N (expedited,
//      segmented, block with CRC): 1008h "npm canopen peer" (const),
//      2001h UNSIGNED32 rw 12345678h, 2002h VISIBLE_STRING rw
//      "npm peer string", 1F50h/1 DOMAIN rw of BYTES (default 1 MiB) of the
//      pattern. Prints "ready node=N" once it answers, then
//      "stored index=I sub=S bytes=N" for each download that changed an entry.
//   listen [--node N]
//      A device with node id N (default 127) and SYNC consumer on 80h that
//      prints one line per frame it sees: "nmt command=CS node=ID" for 000h
//      frames, then "state STATE" when that changed the device's NMT state;
//      "sync" or "sync counter=C" for each SYNC its Sync module accepted.
//      Prints "ready node=N" once it listens.
// --interval: minimum ms between block sub-block frames (npm's
// blockInterval); default 0 = as fast as the event loop goes.
//
// The pattern: byte i is (7 * i + (i >> 8)) mod 256, so a 64 KiB object is not
// a repetition of one 256-byte block (a lost or doubled frame shows).
'use strict';

const path = require('path');

const modules = path.join(__dirname, 'npm', 'node_modules');
let canopen, socketcan;
try {
    canopen = require(path.join(modules, 'canopen'));
    socketcan = require(path.join(modules, 'socketcan'));
}
catch (e) {
    process.stderr.write(`canopen_peer: npm canopen/socketcan not installed in ${modules} `
        + `(run scripts/deps.sh): ${e.message}\n`);
    process.exit(3);
}
const { Device, DataType, AccessType, ObjectType, NmtState } = canopen;

const kUsage = 'usage: canopen_peer.js [--can IFACE] client upload|download --node N --index I --sub S '
    + '[--block] [--file F] [--data HEX | --size BYTES] [--timeout MS] [--interval MS]\n'
    + '       canopen_peer.js [--can IFACE] server --node N [--size BYTES] [--interval MS]\n'
    + '       canopen_peer.js [--can IFACE] listen [--node N]\n';

function usage(message) {
    process.stderr.write(`canopen_peer: ${message}\n${kUsage}`);
    process.exit(2);
}

function pattern(size) {
    const b = Buffer.alloc(size);
    for (let i = 0; i < size; ++i)
        b[i] = (7 * i + (i >> 8)) & 0xff;
    return b;
}

function hex32(v) {
    return (v >>> 0).toString(16).toUpperCase().padStart(8, '0');
}

function hex16(v) {
    return v.toString(16).toUpperCase().padStart(4, '0');
}

/// Options after the command: --name value pairs and bare flags.
function parseOptions(argv, flags) {
    const opts = {};
    for (let i = 0; i < argv.length; ++i) {
        const a = argv[i];
        if (!a.startsWith('--'))
            usage(`unexpected argument '${a}'`);
        const name = a.slice(2);
        if (flags.includes(name)) {
            opts[name] = true;
        }
        else {
            if (i + 1 >= argv.length)
                usage(`${a} needs a value`);
            opts[name] = argv[++i];
        }
    }
    return opts;
}

/// A whole number (decimal, or hex with 0x or a trailing h) in [lo, hi].
function number(opts, name, lo, hi, fallback) {
    const text = opts[name];
    if (text === undefined) {
        if (fallback === undefined)
            usage(`--${name} is required`);
        return fallback;
    }
    let v;
    if (/^0x[0-9a-f]+$/i.test(text))
        v = parseInt(text.slice(2), 16);
    else if (/^[0-9a-f]+h$/i.test(text))
        v = parseInt(text.slice(0, -1), 16);
    else if (/^[0-9]+$/.test(text))
        v = parseInt(text, 10);
    else
        usage(`--${name} '${text}' is not a number`);
    if (v < lo || v > hi)
        usage(`--${name} ${text} out of range ${lo}..${hi}`);
    return v;
}

/// The channel and a device wired to it; frames the device sends go to
/// `onSend` and out, frames the bus carries go to `onFrame`, then to the device.
function attach(iface, id, onFrame, onSend) {
    let channel;
    try {
        channel = socketcan.createRawChannel(iface, false);
    }
    catch (e) {
        process.stderr.write(`canopen_peer: socketcan ${iface}: ${e.message}\n`);
        process.exit(3);
    }
    const device = new Device({ id });
    device.addListener('message', (m) => {
        if (onSend)
            onSend(m);
        channel.send(m);
    });
    channel.addListener('onMessage', (m) => {
        if (m.ext || m.rtr)
            return;
        if (onFrame)
            onFrame(m);
        device.receive(m);
    });
    channel.start();
    return { channel, device };
}

async function runClient(iface, argv) {
    const op = argv[0];
    if (op !== 'upload' && op !== 'download')
        usage('client needs upload or download');
    const opts = parseOptions(argv.slice(1), ['block']);
    const node = number(opts, 'node', 1, 127);
    const index = number(opts, 'index', 0, 0xffff);
    const sub = number(opts, 'sub', 0, 0xff);
    const timeout = number(opts, 'timeout', 1, 600000, 1000);
    const interval = number(opts, 'interval', 0, 1000, 0);
    const block = !!opts.block;

    let data = null;
    if (op === 'download') {
        if (opts.file !== undefined)
            data = require('fs').readFileSync(opts.file);
        else if (opts.data !== undefined) {
            if (!/^([0-9a-f]{2})+$/i.test(opts.data))
                usage('--data needs an even number of hex digits');
            data = Buffer.from(opts.data, 'hex');
        }
        else if (opts.size !== undefined)
            data = pattern(number(opts, 'size', 1, 0xffffffff));
        else
            usage('download needs --file, --data or --size');
    }

    // The client's own node id only matters for NMT; 127 stays out of the way
    // of the servers the tests run (or N-1 when N is 127).
    const ownId = node === 127 ? 126 : 127;
    // Which protocol ran (CiA 301 §7.2.4.3): an upload's is chosen by the
    // server's first answer (scs 2 with e=1 expedited, e=0 segmented; scs 6
    // block), a download's by the client's request (ccs 1 with e; ccs 6).
    let transfer = null;
    const kind = (command, specifier, blockSpecifier) => {
        if (transfer !== null || command.length < 1)
            return;
        const cs = command[0] >> 5;
        if (cs === blockSpecifier)
            transfer = 'block';
        else if (cs === specifier)
            transfer = (command[0] & 0x02) ? 'expedited' : 'segmented';
    };
    const { channel, device } = attach(iface, ownId, (m) => {
        if (op === 'upload' && m.id === 0x580 + node)
            kind(m.data, 2, 6);
    }, (m) => {
        if (op === 'download' && m.id === 0x600 + node)
            kind(m.data, 1, 6);
    });
    device.eds.addSdoClientParameter(node, 0x600 + node, 0x580 + node);
    device.start(); // NMT pre-operational: starts the SDO client

    const args = {
        deviceId: node, index, subIndex: sub, timeout,
        blockTransfer: block, blockInterval: interval,
    };
    const where = `index=${hex16(index)} sub=${sub}`;
    const t0 = process.hrtime.bigint();
    let code = 0;
    try {
        let result;
        if (op === 'upload') {
            result = await device.sdo.upload(args);
        }
        else {
            await device.sdo.download({ ...args, data });
            result = data;
        }
        const seconds = Number(process.hrtime.bigint() - t0) / 1e9;
        let line = `ok ${op} ${where} bytes=${result.length} transfer=${transfer || 'none'}`
            + ` time_s=${seconds.toFixed(6)} bytes_per_s=${Math.round(result.length / seconds)}`;
        if (op === 'upload') {
            if (opts.file !== undefined)
                require('fs').writeFileSync(opts.file, result);
            else if (result.length <= 256)
                line += ` data=${result.toString('hex')}`;
        }
        process.stdout.write(line + '\n');
    }
    catch (e) {
        if (e instanceof canopen.SdoError) {
            process.stdout.write(`abort ${op} ${where} code=${hex32(e.code)}`
                + ` transfer=${transfer || 'none'} message=${e.message}\n`);
            code = 1;
        }
        else {
            process.stderr.write(`canopen_peer: ${op} ${where}: ${e.stack || e}\n`);
            code = 3;
        }
    }
    device.stop();
    channel.stop();
    process.exitCode = code;
}

function runServer(iface, argv) {
    const opts = parseOptions(argv, []);
    const node = number(opts, 'node', 1, 127);
    const size = number(opts, 'size', 0, 64 * 1024 * 1024, 1024 * 1024);
    const interval = number(opts, 'interval', 0, 1000, 0);

    const { device } = attach(iface, node);
    const eds = device.eds;
    // One SDO server channel, the default one of CiA 301 (client id 0: any).
    eds.addSdoServerParameter(0, 0x580 + node, 0x600 + node);
    eds.setDeviceName('npm canopen peer');
    eds.addEntry(0x2001, {
        parameterName: 'peer u32', dataType: DataType.UNSIGNED32,
        accessType: AccessType.READ_WRITE, defaultValue: 0x12345678,
    });
    eds.addEntry(0x2002, {
        parameterName: 'peer string', dataType: DataType.VISIBLE_STRING,
        accessType: AccessType.READ_WRITE, defaultValue: 'npm peer string',
    });
    const program = eds.addEntry(0x1F50, {
        parameterName: 'Program data', objectType: ObjectType.ARRAY,
    });
    const domain = program.addSubObject(1, {
        parameterName: 'Program number 1', dataType: DataType.DOMAIN,
        accessType: AccessType.READ_WRITE,
    });
    domain.raw = pattern(size);

    // npm reports a change of a sub-object as an update of its parent, with
    // the sub-object as the argument (and only when the bytes changed).
    for (const entry of [eds.getEntry(0x2001), eds.getEntry(0x2002), program]) {
        entry.addListener('update', (obj) => {
            const sub = obj === entry ? 0 : obj.subIndex;
            process.stdout.write(`stored index=${hex16(parseInt(entry.key, 16))} sub=${sub}`
                + ` bytes=${obj.raw.length}\n`);
        });
    }

    device.sdoServer.setBlockInterval(interval);
    device.start(); // NMT pre-operational: the SDO server answers from here
    process.stdout.write(`ready node=${node}\n`);
}

function runListen(iface, argv) {
    const opts = parseOptions(argv, []);
    const node = number(opts, 'node', 1, 127, 127);
    const names = {
        [NmtState.INITIALIZING]: 'initializing',
        [NmtState.PRE_OPERATIONAL]: 'pre-operational',
        [NmtState.OPERATIONAL]: 'operational',
        [NmtState.STOPPED]: 'stopped',
    };
    const { device } = attach(iface, node, (m) => {
        if (m.id === 0)
            process.stdout.write(`nmt command=${m.data[0]} node=${m.data[1]}\n`);
    });
    device.eds.setSyncCobId(0x80, { saveDefault: true });
    // npm's Sync hands over the counter byte, undefined for a SYNC without one.
    device.sync.addListener('sync', (counter) => {
        process.stdout.write(counter === undefined ? 'sync\n' : `sync counter=${counter}\n`);
    });
    device.nmt.addListener('changeState', (state) => {
        process.stdout.write(`state ${names[state] || state}\n`);
    });
    device.start();
    process.stdout.write(`ready node=${node}\n`);
}

function main() {
    let argv = process.argv.slice(2);
    let iface = 'vcan0';
    if (argv[0] === '--can') {
        if (argv.length < 2)
            usage('--can needs an interface');
        iface = argv[1];
        argv = argv.slice(2);
    }
    const command = argv[0];
    if (command === 'client')
        runClient(iface, argv.slice(1));
    else if (command === 'server')
        runServer(iface, argv.slice(1));
    else if (command === 'listen')
        runListen(iface, argv.slice(1));
    else if (command === '--help' || command === '-h')
        process.stdout.write(kUsage);
    else
        usage(`unknown command '${command || ''}'`);
}

main();
