// pixelproc_bank_ram: one bank of the core's shading table, 1024 words of 18 bits, one
// write port and one read port on the same clock. The read is registered twice: the word
// at `read_address` before edge E is on `read_data` after edge E + 1. A read of a word
// written at the same edge returns the word's old value.
//
// This is the generic (behavioural) implementation, the one the exported core carries
// and every simulator and generic synthesis reads. The ECP5 flow replaces it with
// synth/ecp5/pixelproc_bank_ram.v (one DP16KD, the second register being the block
// RAM's own output register), which behaves the same except for a read of a word written
// at the same edge (not defined there).
module pixelproc_bank_ram(clock, write_enable, write_address, write_data, read_address, read_data);
    input wire clock;
    input wire write_enable;
    input wire [9:0] write_address;
    input wire [17:0] write_data;
    input wire [9:0] read_address;
    output reg [17:0] read_data;

    reg [17:0] mem [0:1023];
    // The block RAM's read register.
    reg [17:0] read_word;

    initial begin
        read_data = 18'h0;
    end

    always @(posedge clock) begin
        if (write_enable) begin
            mem[write_address] <= write_data;
        end
    end

    always @(posedge clock) begin
        read_word <= mem[read_address];
        read_data <= read_word;
    end
endmodule // pixelproc_bank_ram
